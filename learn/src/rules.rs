//! Rules, not copies: the fitted slices written as a grammar, units grouped into shared
//! rule sets ([`crate::share`]) on a tuple of tags, a tag, or most of a tag (the others
//! keeping rules of their own at a higher priority).

use std::collections::BTreeMap;
use std::fmt::Write as _;

use gmotion::motion::Component;
use gmotion::scene::{Node, Paint, Scene};
use gmotion::signals::Easing;

use crate::Options;
use crate::fit::{self, Change, Clock, Fitted, Move, Pivot, Slice};
use crate::sample::UnitSamples;
use crate::share::{self, Expr, Kind, Shared, Var, Vars};

/// One rule set of the grammar: the units it covers and how many rules it has.
#[derive(Clone, Debug)]
pub struct RuleSet {
    /// The shape tag(s) its rules take, as written.
    pub tags: String,
    /// The units it covers (scene indices).
    pub units: Vec<usize>,
    /// How many rules.
    pub rules: usize,
    /// The stagger it found, as written (an expression of `id`), if its units share it.
    pub stagger: Option<String>,
}

/// The still scene: the art at the reference frame, each unit's opacity and (for a unit of
/// one fill colour) its fill those of frame 0, what the learned paint changes start from.
///
/// For an SVG still (`svg`), each unit's group gets the id its tag reads back from
/// (`tag`, or `tag_N_` when others share it), as SVG keeps no layer names.
pub fn still_scene(reference: &Scene, samples: &[UnitSamples], svg: bool) -> Scene {
    let mut still = reference.clone();
    if svg {
        let ids: Vec<String> = (0..still.shapes.len()).map(|u| svg_id(&still, u)).collect();
        for (u, id) in ids.into_iter().enumerate() {
            let path = still.shapes[u].node_path.clone();
            if let Some(Node::Group(g)) = still.root.node_at_mut(&path) {
                g.id = id;
            }
        }
    }
    for (u, s) in samples.iter().enumerate() {
        crate::clip::drop_canvas_clips(&mut still, u);
        let path = still.shapes[u].node_path.clone();
        let base = fit::base_opacity(s);
        // The opacities above the unit's own node.
        let mut above = f64::from(still.root.opacity);
        for i in 1..path.len() {
            if let Some(Node::Group(g)) = still.root.node_at(&path[..i]) {
                above *= f64::from(g.opacity);
            }
        }
        // Frame 0's opacity goes on the unit's own group (the groups inside it down to
        // its first path, and a one-colour fill, made opaque), its fill on the paths.
        let fill = s.fill.first().copied().flatten().filter(|_| s.one_fill);
        if let Some(node) = still.root.node_at_mut(&path) {
            crate::sample::clear_route_opacity(node);
            if let Some(c) = fill {
                recolour(node, [c[0], c[1], c[2], 1.0]);
            }
            if let Node::Group(g) = node {
                g.opacity = if above > 0.0 {
                    (base / above).clamp(0.0, 1.0) as f32
                } else {
                    0.0
                };
            }
        }
    }
    still
}

/// Whether unit `u` is the only one of its tag, with a tag that has no counter: it is
/// then named by its tag alone.
fn alone(scene: &Scene, u: usize) -> bool {
    let tag = &scene.shapes[u].tag;
    scene.shapes.iter().filter(|s| s.tag == *tag).count() == 1
        && gmotion::tagging::strip_counter(tag) == tag
}

/// The id of unit `u`'s group in an SVG still: its tag alone, else `tag_N_` (N = id + 1),
/// Illustrator's copy suffix, which the SVG importer reads back as the tag (with
/// `units groups`) and keeps as an alias naming the unit alone.
fn svg_id(scene: &Scene, u: usize) -> String {
    let s = &scene.shapes[u];
    if alone(scene, u) {
        s.tag.clone()
    } else {
        format!("{}_{}_", s.tag, s.id + 1)
    }
}

/// Paints every solid fill under `node` in `rgba` (the fill's colour and opacity).
fn recolour(node: &mut Node, rgba: [f32; 4]) {
    match node {
        Node::Path(p) => {
            if let Some(f) = p.fill.as_mut()
                && let Paint::Solid(c) = &mut f.paint
            {
                (c.r, c.g, c.b) = (rgba[0], rgba[1], rgba[2]);
                f.opacity = rgba[3];
            }
        }
        Node::Group(g) => g.children.iter_mut().for_each(|c| recolour(c, rgba)),
        Node::Image(_) => {}
    }
}

/// A number as the grammar writes it: at most `digits` decimals, no trailing zeros.
pub(crate) fn num(x: f64, digits: usize) -> String {
    let s = format!("{x:.digits$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    if s == "-0" { "0".to_string() } else { s }
}

/// Fractions that sum to 1 as a person would write them: each but the last with the
/// fewest decimals that stay within 1e-7 of it (a boundary moves by far less than a frame:
/// 1e-7 of a 10 s animation is a microsecond), the last what the others leave, so that the
/// sum stays 1 as `timesplit` asks (±1e-6). Frame times divided by a frame rate such as
/// 29.97 would otherwise be written 0.24999999 for a quarter.
pub(crate) fn tidy(fractions: &[f64]) -> Vec<String> {
    let shortest = |x: f64, eps: f64| {
        (1..=9)
            .map(|d| num(x, d))
            .find(|t| t.parse::<f64>().is_ok_and(|v| (v - x).abs() <= eps))
            .unwrap_or_else(|| num(x, 9))
    };
    let Some((_, init)) = fractions.split_last() else {
        return Vec::new();
    };
    let mut out: Vec<String> = init.iter().map(|&x| shortest(x, 1e-7)).collect();
    let taken: f64 = out.iter().filter_map(|t| t.parse::<f64>().ok()).sum();
    let last = shortest(1.0 - taken, 1e-9);
    // Every fraction must stay above 0: a sliver (a slice of less than 1e-7 of the
    // whole) is written exactly as measured, the others with it.
    if out
        .iter()
        .chain([&last])
        .any(|t| t.parse::<f64>().is_ok_and(|v| v <= 0.0))
    {
        return fractions.iter().map(|&x| num(x, 9)).collect();
    }
    out.push(last);
    out
}

/// An easing as the grammar writes it (`None` for linear, the default).
pub(crate) fn ease_text(e: &Easing) -> Option<String> {
    if *e == Easing::Linear {
        return None;
    }
    for name in ["ease", "ease-in", "ease-out", "ease-in-out"] {
        if Easing::from_call(name, &[]).is_ok_and(|n| n == *e) {
            return Some(name.to_string());
        }
    }
    match e {
        Easing::CubicBezier(c) => Some(format!(
            "cubic({}, {}, {}, {})",
            num(c[0], 4),
            num(c[1], 4),
            num(c[2], 4),
            num(c[3], 4)
        )),
        _ => None,
    }
}

/// A transform's components as written, their numbers taken from `vals` (the layout of
/// [`share::numbers`]: the components', then a world pivot's point).
fn transform_text<'a>(
    comps: &[Component],
    pivot: Pivot,
    vals: &mut impl Iterator<Item = &'a (Expr, Kind)>,
) -> String {
    let mut next = || {
        vals.next()
            .map_or_else(|| "0".to_string(), |(e, k)| e.text(k.digits()))
    };
    let mut parts: Vec<String> = comps
        .iter()
        .map(|c| match *c {
            Component::Translate(_) => format!("translate({}, {})", next(), next()),
            Component::Rotate(_) => format!("rotate({})", next()),
            Component::Scale(_) => format!("scale({}, {})", next(), next()),
            Component::Skew(..) => format!("skew({}, {})", next(), next()),
            Component::Matrix(_) => {
                let m: Vec<String> = (0..6).map(|_| next()).collect();
                format!("matrix({})", m.join(", "))
            }
        })
        .collect();
    if parts.is_empty() {
        parts.push("translate(0, 0)".into());
    }
    if let Pivot::World(_) = pivot
        && let (Some((x, kx)), Some((y, ky))) = (vals.next(), vals.next())
        && !(x.is_constant() && x.c == 0.0 && y.is_constant() && y.c == 0.0)
    {
        let (dx, dy) = (kx.digits(), ky.digits());
        parts.insert(0, format!("translate({}, {})", x.text(dx), y.text(dy)));
        parts.push(format!(
            "translate({}, {})",
            x.times(-1.0).text(dx),
            y.times(-1.0).text(dy)
        ));
    }
    parts.join(" ")
}

/// The times of one rule set's slices, written: per level-1 slice its fraction and
/// offset, per inner slice the same relative to its parent.
struct Times {
    /// Level-1 fractions of the whole duration.
    fractions: Vec<String>,
    /// Level-1 offsets.
    delays: Vec<String>,
    /// Inner fractions (of the parent's duration `d`) and offsets, per level-1 slice.
    inner: Vec<(Vec<String>, Vec<String>)>,
}

/// Digits of times written (seconds): far below a frame.
const TIME_DIGITS: usize = 6;

/// How units are told apart in a shared set: `k` counts them in paint order.
fn vars_of(still: &Scene, units: &[usize]) -> Vec<Vars> {
    let mut by_z: Vec<usize> = units.to_vec();
    by_z.sort_by_key(|&u| still.shapes[u].z);
    units
        .iter()
        .map(|&u| {
            let s = &still.shapes[u];
            let c = s.centroid;
            Vars {
                id: s.id as f64,
                k: by_z.iter().position(|&v| v == u).unwrap_or(0) as f64,
                cx: c.x,
                cy: c.y,
                dist: (c.x - still.width / 2.0).hypot(c.y - still.height / 2.0),
            }
        })
        .collect()
}

/// How the still scene names unit `u`, alone. The Lottie writer names a layer after its
/// tag when that is unique and has no counter, else `tag N` (N = id + 1), which reads back
/// as the tag with the alias `tag_N`; an SVG still has the group ids of [`svg_id`].
fn address(still: &Scene, u: usize, svg: bool) -> String {
    let shape = &still.shapes[u];
    if alone(still, u) {
        shape.tag.clone()
    } else if svg {
        svg_id(still, u)
    } else {
        format!("{}_{}", shape.tag, shape.id + 1)
    }
}

/// The errors of one unit (its index, largest pixel and opacity errors) as the shared set
/// that covers it plays it.
pub type Played = (usize, f64, f64);

/// The grammar for the still scene `still` and the fitted units (their trims, morphs and
/// strokes, learned apart), its rule sets, and the errors of the units that shared sets
/// cover, as those play them.
#[allow(clippy::too_many_arguments)]
pub fn write(
    still: &Scene,
    samples: &[UnitSamples],
    fitted: &[Fitted],
    trims: &[Option<crate::trim::Fitted>],
    morphs: &[Option<crate::outline::Fitted>],
    strokes: &[Option<crate::stroke::Fitted>],
    clock: Clock,
    still_name: &str,
    svg: bool,
    opts: &Options,
) -> (String, Vec<RuleSet>, Vec<Played>) {
    // Units by tag, in id order.
    let mut by_tag: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
    for (u, s) in still.shapes.iter().enumerate() {
        if !fitted[u].slices.is_empty() {
            by_tag.entry(s.tag.as_str()).or_default().push(u);
        }
    }
    for units in by_tag.values_mut() {
        units.sort_by_key(|&u| still.shapes[u].id);
    }
    // A shared set must cover every drawing of its tags: its first rule takes them all
    // through `all`, which takes no rig (and `k` counts drawings only), so rigs keep
    // rules of their own.
    let drawings = |tag: &str| {
        still
            .shapes
            .iter()
            .filter(|s| s.tag == tag && !s.rig)
            .count()
    };
    // Morphs and strokes are nested in a unit's own slices: such a unit shares no set.
    let plain = |u: usize| morphs[u].is_none() && strokes[u].is_none();
    let whole = |tag: &str, units: &[usize]| {
        let moving = units.iter().filter(|&&u| !still.shapes[u].rig).count();
        moving > 0 && moving == drawings(tag) && units.iter().all(|&u| plain(u))
    };
    let mut body = String::new();
    let mut sets = Vec::new();
    // The errors of the units in shared sets, as those play them.
    let mut played: Vec<Played> = Vec::new();
    let mut shared_set = |body: &mut String, tags: String, units: Vec<usize>, shared: Shared| {
        played.extend(
            units
                .iter()
                .zip(&shared.errors)
                .map(|(&u, &(px, op))| (u, px, op)),
        );
        let stagger = shared
            .exprs
            .iter()
            .take(2 * shared.template.len())
            .skip(1)
            .step_by(2)
            .find(|(e, _)| !e.is_constant())
            .map(|(e, k)| e.text(k.digits()));
        let range = |v: Var| shared.range(v);
        let rules = rule_set(
            body,
            &tags,
            &shared.template,
            (&shared.exprs, &range),
            clock,
            UnitPart::default(),
        );
        RuleSet {
            tags,
            units,
            rules,
            stagger,
        }
    };
    // Tags whose units say the same kinds of change share one set on the tuple of them
    // when they can (`k`, `cx`, `cy` tell their units apart across tags).
    let mut done: Vec<&str> = Vec::new();
    let tags: Vec<&str> = by_tag.keys().copied().collect();
    for (i, &tag) in tags.iter().enumerate() {
        if done.contains(&tag) || !whole(tag, &by_tag[tag]) {
            continue;
        }
        let first = &fitted[by_tag[tag][0]].slices;
        let cluster: Vec<&str> = std::iter::once(tag)
            .chain(tags[i + 1..].iter().copied().filter(|t| {
                !done.contains(t)
                    && whole(t, &by_tag[t])
                    && share::same_kinds(first, &fitted[by_tag[t][0]].slices)
            }))
            .collect();
        if cluster.len() < 2 {
            continue;
        }
        let mut units: Vec<usize> = cluster
            .iter()
            .flat_map(|t| by_tag[t].iter().copied())
            .filter(|&u| !still.shapes[u].rig)
            .collect();
        units.sort_by_key(|&u| still.shapes[u].z);
        let vars = vars_of(still, &units);
        if let Some(shared) = share::share(&units, &vars, samples, fitted, clock, opts) {
            let tags = format!("({})", cluster.join(", "));
            sets.push(shared_set(&mut body, tags, units, shared));
            done.extend(cluster);
        }
    }
    for (tag, units) in by_tag {
        let (rigs, drawn): (Vec<usize>, Vec<usize>) =
            units.iter().partition(|&&u| still.shapes[u].rig);
        let mut own = units.clone();
        // Units of a tag whose shared set is not theirs: they keep rules of their own,
        // which take their timeline first.
        let mut exceptions: Vec<usize> = Vec::new();
        if done.contains(&tag) {
            own = rigs;
        } else if drawn.len() > 1 && whole(tag, &units) {
            let vars = vars_of(still, &drawn);
            if let Some(shared) = share::share(&drawn, &vars, samples, fitted, clock, opts) {
                sets.push(shared_set(&mut body, tag.to_string(), drawn, shared));
                own = rigs;
            } else if let Some(class) = largest_class(&drawn, fitted)
                && class.len() < drawn.len()
            {
                // The most units that say the same kinds of change share a set; `k`
                // still counts every drawing the set's rules take.
                let cvars: Vec<Vars> = class
                    .iter()
                    .filter_map(|u| drawn.iter().position(|v| v == u).map(|i| vars[i]))
                    .collect();
                if let Some(shared) = share::share(&class, &cvars, samples, fitted, clock, opts) {
                    exceptions = drawn
                        .iter()
                        .copied()
                        .filter(|u| !class.contains(u))
                        .collect();
                    sets.push(shared_set(&mut body, tag.to_string(), class, shared));
                    own = rigs;
                    own.extend(&exceptions);
                }
            }
        }
        for u in own {
            let address = address(still, u, svg);
            let own: Vec<(Expr, Kind)> = share::numbers(&fitted[u].slices)
                .into_iter()
                .map(|(x, k)| (Expr::constant(x), k))
                .collect();
            let rules = rule_set(
                &mut body,
                &address,
                &fitted[u].slices,
                (&own, &|_| 0.0),
                clock,
                UnitPart {
                    exception: exceptions.contains(&u),
                    morph: morphs[u].as_ref(),
                    stroke: strokes[u].as_ref(),
                },
            );
            sets.push(RuleSet {
                tags: address,
                units: vec![u],
                rules,
                stagger: None,
            });
        }
    }
    // A unit that otherwise holds still gets the rules of its trim, else of its outline's
    // morphs, else of its stroke's changes (each fitted only where the one before is not).
    for u in 0..still.shapes.len() {
        if !fitted[u].slices.is_empty() {
            continue;
        }
        let address = address(still, u, svg);
        let rules = if let Some(t) = &trims[u] {
            crate::trim::write(&mut body, &address, t, clock)
        } else if let Some(m) = &morphs[u] {
            let rules = (m.leaves.iter().enumerate())
                .map(|(i, pieces)| crate::outline::write(&mut body, "all", &address, i, pieces))
                .sum();
            body.push('\n');
            rules
        } else if let Some(st) = &strokes[u] {
            let rules = (st.leaves.iter().enumerate())
                .map(|(i, pieces)| crate::stroke::write(&mut body, "all", &address, i, pieces))
                .sum();
            body.push('\n');
            rules
        } else {
            continue;
        };
        sets.push(RuleSet {
            tags: address,
            units: vec![u],
            rules,
            stagger: None,
        });
    }
    let total: usize = sets.iter().map(|s| s.rules).sum();
    let mut head = String::new();
    let _ = writeln!(
        head,
        "# Learned by `gmotion learn`: {} units, {total} rules in {} rule sets.",
        still.shapes.len(),
        sets.len()
    );
    let _ = writeln!(head, "scene \"{}\"", still_name.replace('"', "\\\""));
    let _ = writeln!(head, "duration {}s", num(clock.duration, 6));
    let _ = writeln!(head, "fps {}", num(clock.fps, 6));
    // Each rule rewrites its units once: more rules than the default bound of expansion
    // steps need a larger one (at most the `steps` limit's default).
    if total >= 5_000 {
        let _ = writeln!(head, "max_steps {}", (2 * total + 100).min(100_000));
    }
    if svg {
        // Each unit is a group of the still SVG, tagged by its id.
        let _ = writeln!(head, "units groups");
    }
    head.push('\n');
    head.push_str(&body);
    (head, sets, played)
}

/// Each variable's largest magnitude over a set's units, what its numbers' rounding is
/// weighed by.
type Range<'a> = &'a dyn Fn(Var) -> f64;

/// The largest class of `units` whose slices say the same kinds of change (at least
/// two units), in `units`' order.
fn largest_class(units: &[usize], fitted: &[Fitted]) -> Option<Vec<usize>> {
    let mut classes: Vec<Vec<usize>> = Vec::new();
    for &u in units {
        match classes
            .iter_mut()
            .find(|c| share::same_kinds(&fitted[c[0]].slices, &fitted[u].slices))
        {
            Some(c) => c.push(u),
            None => classes.push(vec![u]),
        }
    }
    classes
        .into_iter()
        .filter(|c| c.len() > 1)
        .max_by_key(|c| c.len())
}

/// What one unit's own rule set adds to what a shared one writes: its slices named after
/// it when it is an exception to its tag's shared set, and the changes nested in the
/// leaves of its slices.
#[derive(Clone, Copy, Default)]
struct UnitPart<'a> {
    /// Whether the unit is an exception to its tag's shared set.
    exception: bool,
    /// Its outline's morphs.
    morph: Option<&'a crate::outline::Fitted>,
    /// Its stroke's changes.
    stroke: Option<&'a crate::stroke::Fitted>,
}

/// Writes the rules of one set on shape tag `tag` (a tag, or a tuple of tags), its
/// numbers `exprs` (the layout of [`share::numbers`]); returns how many. An exception to
/// a set shared by the rest of its tag (`unit.exception`) names its slices after `tag` (the
/// shared rules must not take them) and takes the whole timeline first (`priority=1`);
/// its morphs and stroke changes are written nested in the leaves of its slices.
fn rule_set(
    out: &mut String,
    tag: &str,
    slices: &[Slice],
    (exprs, range): (&[(Expr, Kind)], Range),
    clock: Clock,
    unit: UnitPart,
) -> usize {
    let UnitPart {
        exception,
        morph,
        stroke,
    } = unit;
    let pre = if exception {
        format!("{tag}_")
    } else {
        String::new()
    };
    let prio = |slice: &str| {
        if exception && slice == "all" {
            " priority=1"
        } else {
            ""
        }
    };
    let n_times = 2 * (slices.len() + slices.iter().map(|s| s.inner.len()).sum::<usize>());
    let (times, values) = exprs.split_at(n_times.min(exprs.len()));
    let times: Vec<Expr> = times.iter().map(|(e, _)| e.clone()).collect();
    let layout = Times::of(slices, &times, clock, range);
    // The moves' values, level-1 moves first, as [`share::numbers`] lists them.
    let mut vals = values.iter();
    let mut rules = 0;
    let name = |k: usize| match slices[k].twin_of {
        Some(i) => format!("inv_{pre}p{i}"),
        None => format!("{pre}p{k}"),
    };
    let whole = slices.len() == 1;
    if !whole {
        let outs: Vec<String> = (0..slices.len()).map(name).collect();
        let _ = writeln!(
            out,
            "timesplit({}) : [all, {tag}] -> [{}]{}",
            layout.fractions.join(", "),
            outs.join(", "),
            prio("all")
        );
        rules += 1;
    }
    let mut current: Vec<String> = (0..slices.len())
        .map(|k| {
            if whole {
                "all".to_string()
            } else {
                format!("{pre}p{k}")
            }
        })
        .collect();
    for (k, s) in slices.iter().enumerate() {
        let Some(m) = &s.play else { continue };
        // Only affine moves play at level 1; anything else would be skipped, its numbers
        // with it.
        let Change::Affine(comps, pivot) = &m.change else {
            continue;
        };
        let ref_ = if *pivot == Pivot::Local {
            "local"
        } else {
            "world"
        };
        let ease = ease_text(&m.ease).map_or(String::new(), |e| format!(", ease={e}"));
        let _ = writeln!(
            out,
            "animate(affine, {ref_}, {}, {}{ease}) : [{}, {tag}] -> [{pre}m{k}]{}",
            layout.delays[k],
            transform_text(comps, *pivot, &mut vals),
            current[k],
            prio(&current[k])
        );
        current[k] = format!("{pre}m{k}");
        rules += 1;
    }
    // The name each leaf of the slices ends with (see `outline::leaves`), for the morphs.
    let mut leaves: Vec<Vec<String>> = current.iter().map(|c| vec![c.clone()]).collect();
    for (k, s) in slices.iter().enumerate() {
        if s.inner.is_empty() {
            continue;
        }
        leaves[k].clear();
        let (fractions, delays) = &layout.inner[k];
        let one = s.inner.len() == 1;
        if !one {
            let outs: Vec<String> = (0..s.inner.len())
                .map(|l| format!("{pre}p{k}_{l}"))
                .collect();
            let _ = writeln!(
                out,
                "timesplit({}) : [{}, {tag}] -> [{}]{}",
                fractions.join(", "),
                current[k],
                outs.join(", "),
                prio(&current[k])
            );
            rules += 1;
        }
        for (l, i) in s.inner.iter().enumerate() {
            if let Some(Move {
                ease,
                change: Change::Paint(change),
                ..
            }) = &i.play
            {
                let ease = ease_text(ease).map_or(String::new(), |e| format!(", ease={e}"));
                // One paint slice is the whole slice: no split.
                let mut slice = if one {
                    current[k].clone()
                } else {
                    format!("{pre}p{k}_{l}")
                };
                if change.opacity.is_some()
                    && let Some((v, kind)) = vals.next()
                {
                    let _ = writeln!(
                        out,
                        "animate(opacity, local, {}, {}{ease}) : [{slice}, {tag}] -> [{pre}o{k}_{l}]{}",
                        delays[l],
                        v.text(kind.digits()),
                        prio(&slice)
                    );
                    slice = format!("{pre}o{k}_{l}");
                    rules += 1;
                }
                if change.fill.is_some() {
                    let rgb: Vec<String> = (0..3)
                        .map(|_| vals.next().map_or("0".into(), |(e, k)| e.text(k.digits())))
                        .collect();
                    let _ = writeln!(
                        out,
                        "animate(fill, local, {}, rgb({}){ease}) : [{slice}, {tag}] -> [{pre}f{k}_{l}]{}",
                        delays[l],
                        rgb.join(", "),
                        prio(&slice)
                    );
                    slice = format!("{pre}f{k}_{l}");
                    rules += 1;
                }
                leaves[k].push(slice);
            } else {
                leaves[k].push(if one {
                    current[k].clone()
                } else {
                    format!("{pre}p{k}_{l}")
                });
            }
        }
    }
    if let Some(m) = morph {
        for (i, (name, pieces)) in leaves.iter().flatten().zip(&m.leaves).enumerate() {
            rules += crate::outline::write(out, name, tag, i, pieces);
        }
    } else if let Some(st) = stroke {
        for (i, (name, pieces)) in leaves.iter().flatten().zip(&st.leaves).enumerate() {
            rules += crate::stroke::write(out, name, tag, i, pieces);
        }
    }
    out.push('\n');
    rules
}

impl Times {
    /// The written times of `slices` from their expressions (the times of
    /// [`share::numbers`]: per level-1 slice its end and offset, then the inner ones').
    ///
    /// Fractions that vary are written as short as keeps every boundary within a
    /// ten-thousandth of a frame over the units (`range`: each variable's largest
    /// magnitude), the last what the others leave, so that they sum to 1 exactly.
    fn of(slices: &[Slice], times: &[Expr], clock: Clock, range: &dyn Fn(Var) -> f64) -> Times {
        let duration = clock.duration;
        let zero = Expr::constant(0.0);
        let at = |k: usize| times.get(k).unwrap_or(&zero);
        let mut parts = Vec::new();
        let mut delays = Vec::new();
        let mut k = 0;
        let mut prev = zero.clone();
        for _ in slices {
            let end = at(k);
            parts.push(end.plus(-1.0, &prev).times(1.0 / duration));
            delays.push(at(k + 1).text(TIME_DIGITS));
            prev = end.clone();
            k += 2;
        }
        let fractions = if parts.iter().all(|p| p.is_constant()) {
            tidy(&parts.iter().map(|p| p.c).collect::<Vec<_>>())
        } else {
            let eps = 1e-4 / (clock.fps * duration);
            let mut written: Vec<Expr> = Vec::new();
            let mut left = Expr::constant(1.0);
            for (i, p) in parts.iter().enumerate() {
                let e = if i + 1 == parts.len() {
                    left.clone()
                } else {
                    p.rounded_within(eps, range)
                };
                left = left.plus(-1.0, &e);
                written.push(e);
            }
            written.iter().map(|p| p.text(9)).collect()
        };
        let mut inner = Vec::new();
        for (j, s) in slices.iter().enumerate() {
            let mut fr = Vec::new();
            let mut fixed = Vec::new();
            let mut de = Vec::new();
            let start = if j == 0 {
                zero.clone()
            } else {
                at(2 * (j - 1)).clone()
            };
            let parent = at(2 * j).plus(-1.0, &start);
            let mut prev = start;
            for _ in &s.inner {
                let end = at(k);
                let len = end.plus(-1.0, &prev);
                fr.push(if len.is_constant() && parent.is_constant() {
                    // A fixed length: its fraction of the fixed parent.
                    fixed.push(len.c / parent.c);
                    num(len.c / parent.c, 9)
                } else {
                    format!("({}) / d", len.text(TIME_DIGITS))
                });
                de.push(at(k + 1).text(TIME_DIGITS));
                prev = end.clone();
                k += 2;
            }
            if fixed.len() == fr.len() {
                fr = tidy(&fixed);
            }
            inner.push((fr, de));
        }
        Times {
            fractions,
            delays,
            inner,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::tidy;

    fn sum(t: &[String]) -> f64 {
        t.iter().map(|x| x.parse::<f64>().unwrap()).sum()
    }

    #[test]
    fn fractions_are_written_as_a_person_would_and_still_sum_to_one() {
        let t = tidy(&[0.24999999, 0.24999999, 0.50000002]);
        assert_eq!(t, ["0.25", "0.25", "0.5"]);
        let t = tidy(&[0.1, 0.2, 0.7]);
        assert_eq!(t, ["0.1", "0.2", "0.7"]);
        // Thirds cannot be short: what is kept is within 1e-7, and the sum is 1.
        let t = tidy(&[1.0 / 3.0; 3]);
        assert!(
            t.iter()
                .all(|x| (x.parse::<f64>().unwrap() - 1.0 / 3.0).abs() <= 1e-7)
        );
        assert!((sum(&t) - 1.0).abs() <= 1e-9, "{t:?}");
    }

    #[test]
    fn a_sliver_is_kept_as_measured_never_rounded_to_zero() {
        let t = tidy(&[0.49999998, 0.49999998, 0.000000041]);
        assert!(t.iter().all(|x| x.parse::<f64>().unwrap() > 0.0), "{t:?}");
        assert!((sum(&t) - 1.0).abs() <= 1e-6, "{t:?}");
    }
}
