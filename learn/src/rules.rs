//! Rules, not copies: the fitted slices written as a grammar, the units of one tag sharing
//! one rule set when their slices agree up to a stagger (times and offsets `a + b·id`,
//! fitted by least squares and kept only when every unit stays within the tolerance).

use std::collections::BTreeMap;
use std::fmt::Write as _;

use gmotion::motion::Component;
use gmotion::scene::{Node, Paint, Scene};
use gmotion::signals::Easing;

use crate::Options;
use crate::fit::{self, Change, Clock, Fitted, Move, Pivot, Slice};
use crate::sample::UnitSamples;

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

/// `a + b·id` as written.
fn linear(a: f64, b: f64, digits: usize) -> String {
    let b_text = num(b.abs(), digits);
    if b_text == "0" {
        return num(a, digits);
    }
    let a_text = num(a, digits);
    let sign = if b < 0.0 { "-" } else { "+" };
    if a_text == "0" && b > 0.0 {
        format!("{b_text} * id")
    } else {
        format!("{a_text} {sign} {b_text} * id")
    }
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

/// A transform's components as written.
fn transform_text(comps: &[Component], pivot: Pivot) -> String {
    let mut parts: Vec<String> = comps
        .iter()
        .map(|c| match *c {
            Component::Translate(v) => format!("translate({}, {})", num(v.x, 4), num(v.y, 4)),
            Component::Rotate(a) => format!("rotate({})", num(a, 4)),
            Component::Scale(k) => format!("scale({}, {})", num(k.x, 6), num(k.y, 6)),
            Component::Skew(x, y) => format!("skew({}, {})", num(x, 4), num(y, 4)),
            Component::Matrix(m) => {
                let c = m.as_coeffs();
                format!(
                    "matrix({}, {}, {}, {}, {}, {})",
                    num(c[0], 6),
                    num(c[1], 6),
                    num(c[2], 6),
                    num(c[3], 6),
                    num(c[4], 4),
                    num(c[5], 4)
                )
            }
        })
        .collect();
    if parts.is_empty() {
        parts.push("translate(0, 0)".into());
    }
    if let Pivot::World(p) = pivot
        && (p.x != 0.0 || p.y != 0.0)
    {
        parts.insert(0, format!("translate({}, {})", num(p.x, 4), num(p.y, 4)));
        parts.push(format!("translate({}, {})", num(-p.x, 4), num(-p.y, 4)));
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

/// A unit's times, as numbers in the layout [`Times`] writes: level-1 boundaries and
/// delays, then per slice the inner boundaries and delays.
fn times_of(slices: &[Slice]) -> Vec<f64> {
    let mut v = Vec::new();
    for s in slices {
        v.push(s.t1);
        v.push(s.play.as_ref().map_or(0.0, |m| m.delay));
    }
    for s in slices {
        for i in &s.inner {
            v.push(i.t1);
            v.push(i.play.as_ref().map_or(0.0, |m| m.delay));
        }
    }
    v
}

/// Writes `slices` back with new times (the layout of [`times_of`]).
fn with_times(slices: &[Slice], times: &[f64]) -> Vec<Slice> {
    let mut out = slices.to_vec();
    let mut k = 0;
    let mut t0 = 0.0;
    for s in out.iter_mut() {
        s.t0 = t0;
        s.t1 = times[k];
        if let Some(m) = &mut s.play {
            m.delay = times[k + 1];
        }
        k += 2;
        t0 = s.t1;
    }
    for s in out.iter_mut() {
        let mut t0 = s.t0;
        for i in s.inner.iter_mut() {
            i.t0 = t0;
            i.t1 = times[k];
            if let Some(m) = &mut i.play {
                m.delay = times[k + 1];
            }
            k += 2;
            t0 = i.t1;
        }
    }
    out
}

/// Whether two units' slices say the same changes (times aside).
fn same_changes(a: &[Slice], b: &[Slice], opts: &Options) -> bool {
    fn comps_close(x: &[Component], y: &[Component], tol: f64) -> bool {
        x.len() == y.len()
            && x.iter().zip(y).all(|(p, q)| match (p, q) {
                (Component::Translate(u), Component::Translate(v)) => (*u - *v).hypot() <= tol,
                (Component::Rotate(u), Component::Rotate(v)) => (u - v).abs() <= 1e-3,
                (Component::Scale(u), Component::Scale(v)) => (*u - *v).hypot() <= 1e-4,
                (Component::Skew(a, b), Component::Skew(c, d)) => {
                    (a - c).abs() <= 1e-3 && (b - d).abs() <= 1e-3
                }
                (Component::Matrix(u), Component::Matrix(v)) => u
                    .as_coeffs()
                    .iter()
                    .zip(v.as_coeffs())
                    .all(|(p, q)| (p - q).abs() <= 1e-4),
                _ => false,
            })
    }
    fn play_same(x: &Option<Move>, y: &Option<Move>, opts: &Options) -> bool {
        match (x, y) {
            (None, None) => true,
            (Some(p), Some(q)) => {
                p.ease == q.ease
                    && match (&p.change, &q.change) {
                        (Change::Affine(c, pv), Change::Affine(d, qv)) => {
                            pv == qv && comps_close(c, d, opts.tolerance * 0.5)
                        }
                        (Change::Paint(u), Change::Paint(v)) => {
                            let near =
                                |a: f64, b: f64| (a - b).abs() <= opts.opacity_tolerance * 0.5;
                            match ((u.opacity, v.opacity), (u.fill, v.fill)) {
                                (
                                    (None, None) | (Some(_), Some(_)),
                                    (None, None) | (Some(_), Some(_)),
                                ) => {
                                    u.opacity.zip(v.opacity).is_none_or(|(a, b)| near(a, b))
                                        && u.fill.zip(v.fill).is_none_or(|(a, b)| {
                                            a.iter().zip(&b).all(|(x, y)| near(*x, *y))
                                        })
                                }
                                _ => false,
                            }
                        }
                        _ => false,
                    }
            }
            _ => false,
        }
    }
    a.len() == b.len()
        && a.iter().zip(b).all(|(s, t)| {
            s.twin_of == t.twin_of
                && play_same(&s.play, &t.play, opts)
                && s.inner.len() == t.inner.len()
                && s.inner
                    .iter()
                    .zip(&t.inner)
                    .all(|(i, j)| play_same(&i.play, &j.play, opts))
        })
}

/// Least squares `y ≈ a + b·x`.
fn fit_line(xs: &[f64], ys: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let mx = xs.iter().sum::<f64>() / n;
    let my = ys.iter().sum::<f64>() / n;
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    if sxx <= 0.0 {
        return (my, 0.0);
    }
    let sxy: f64 = xs.iter().zip(ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let b = sxy / sxx;
    (my - b * mx, b)
}

/// Digits of times written (seconds): far below a frame.
const TIME_DIGITS: usize = 6;

/// Tries to share one rule set among `units` (one tag, ids 0…): the same changes, times
/// fitted as `a + b·id`. The shared times, as (a, b) pairs, when every unit stays within
/// the tolerance with them.
fn share(
    units: &[usize],
    ids: &[usize],
    samples: &[UnitSamples],
    fitted: &[Fitted],
    clock: Clock,
    opts: &Options,
) -> Option<Vec<(f64, f64)>> {
    let first = &fitted[units[0]].slices;
    if first.is_empty()
        || !units
            .iter()
            .all(|&u| same_changes(first, &fitted[u].slices, opts))
    {
        return None;
    }
    let xs: Vec<f64> = ids.iter().map(|&i| i as f64).collect();
    let all: Vec<Vec<f64>> = units.iter().map(|&u| times_of(&fitted[u].slices)).collect();
    let lines: Vec<(f64, f64)> = (0..all[0].len())
        .map(|k| {
            let ys: Vec<f64> = all.iter().map(|t| t[k]).collect();
            let (a, b) = fit_line(&xs, &ys);
            // As written, so the check below sees what `animate` will.
            let r = |x: f64| num(x, TIME_DIGITS).parse().unwrap_or(x);
            (r(a), r(b))
        })
        .collect();
    for (&u, &id) in units.iter().zip(ids) {
        let times: Vec<f64> = lines.iter().map(|(a, b)| a + b * id as f64).collect();
        let slices = with_times(first, &times);
        // Every slice must keep a length and its offset must fit in it.
        if slices
            .iter()
            .chain(slices.iter().flat_map(|s| &s.inner))
            .any(|s| {
                s.t1 - s.t0 <= 1e-9
                    || s.play
                        .as_ref()
                        .is_some_and(|m| m.delay < -1e-9 || m.delay >= s.t1 - s.t0)
            })
        {
            return None;
        }
        let pts = fit::points_of(&samples[u]);
        let (px, op) = fit::errors(&samples[u], &pts, clock, &slices);
        let own = &fitted[u];
        if px > opts.tolerance.max(own.max_px) + 1e-9
            || op > opts.opacity_tolerance.max(own.max_opacity) + 1e-9
        {
            return None;
        }
    }
    Some(lines)
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

/// The grammar for the still scene `still` and the fitted units (their trims, learned
/// apart, in `trims`), and its rule sets.
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
) -> (String, Vec<RuleSet>) {
    // Units by tag, in id order.
    let mut by_tag: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
    for (u, s) in still.shapes.iter().enumerate() {
        if !fitted[u].slices.is_empty() {
            by_tag.entry(s.tag.as_str()).or_default().push(u);
        }
    }
    let count = |tag: &str| still.shapes.iter().filter(|s| s.tag == tag).count();
    let mut body = String::new();
    let mut sets = Vec::new();
    for (tag, mut units) in by_tag {
        units.sort_by_key(|&u| still.shapes[u].id);
        let ids: Vec<usize> = units.iter().map(|&u| still.shapes[u].id).collect();
        // A shared set must cover every shape of the tag (the rules take them all).
        if units.len() > 1
            && units.len() == count(tag)
            && units
                .iter()
                .all(|&u| morphs[u].is_none() && strokes[u].is_none())
            && let Some(lines) = share(&units, &ids, samples, fitted, clock, opts)
        {
            let texts: Vec<String> = lines
                .iter()
                .map(|(a, b)| linear(*a, *b, TIME_DIGITS))
                .collect();
            let stagger = texts
                .iter()
                .skip(1)
                .step_by(2)
                .find(|t| t.contains("id"))
                .cloned();
            let rules = rule_set(
                &mut body,
                tag,
                &fitted[units[0]].slices,
                &SetTimes::Shared(&lines),
                clock,
                None,
                None,
            );
            sets.push(RuleSet {
                tags: tag.to_string(),
                units,
                rules,
                stagger,
            });
            continue;
        }
        for u in units {
            let address = address(still, u, svg);
            let rules = rule_set(
                &mut body,
                &address,
                &fitted[u].slices,
                &SetTimes::Own,
                clock,
                morphs[u].as_ref(),
                strokes[u].as_ref(),
            );
            sets.push(RuleSet {
                tags: address,
                units: vec![u],
                rules,
                stagger: None,
            });
        }
    }
    // A unit drawn on or off by trim paths, and otherwise still, gets its trim rules.
    for (u, t) in trims.iter().enumerate() {
        if let Some(t) = t
            && fitted[u].slices.is_empty()
        {
            let address = address(still, u, svg);
            let rules = crate::trim::write(&mut body, &address, t, clock);
            sets.push(RuleSet {
                tags: address,
                units: vec![u],
                rules,
                stagger: None,
            });
        }
    }
    // A unit whose outline changes, and otherwise still, gets its morph rules.
    for (u, m) in morphs.iter().enumerate() {
        if let Some(m) = m
            && fitted[u].slices.is_empty()
            && trims[u].is_none()
        {
            let address = address(still, u, svg);
            let mut rules = 0;
            for (i, pieces) in m.leaves.iter().enumerate() {
                rules += crate::outline::write(&mut body, "all", &address, i, pieces);
            }
            body.push('\n');
            sets.push(RuleSet {
                tags: address,
                units: vec![u],
                rules,
                stagger: None,
            });
        }
    }
    // Likewise a still unit whose stroke changes.
    for (u, st) in strokes.iter().enumerate() {
        if let Some(st) = st
            && fitted[u].slices.is_empty()
            && trims[u].is_none()
            && morphs[u].is_none()
        {
            let address = address(still, u, svg);
            let mut rules = 0;
            for (i, pieces) in st.leaves.iter().enumerate() {
                rules += crate::stroke::write(&mut body, "all", &address, i, pieces);
            }
            body.push('\n');
            sets.push(RuleSet {
                tags: address,
                units: vec![u],
                rules,
                stagger: None,
            });
        }
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
    (head, sets)
}

/// Where a rule set's times come from.
enum SetTimes<'a> {
    /// The unit's own slices.
    Own,
    /// Shared lines `a + b·id`, in the layout of [`times_of`].
    Shared(&'a [(f64, f64)]),
}

/// Writes the rules of one set on shape tag `tag`; returns how many.
fn rule_set(
    out: &mut String,
    tag: &str,
    slices: &[Slice],
    times: &SetTimes,
    clock: Clock,
    morph: Option<&crate::outline::Fitted>,
    stroke: Option<&crate::stroke::Fitted>,
) -> usize {
    let duration = clock.duration;
    let lines: Vec<(f64, f64)> = match times {
        SetTimes::Own => times_of(slices).into_iter().map(|t| (t, 0.0)).collect(),
        SetTimes::Shared(l) => l.to_vec(),
    };
    let layout = Times::of(slices, &lines, duration);
    let mut rules = 0;
    let name = |k: usize| match slices[k].twin_of {
        Some(i) => format!("inv_p{i}"),
        None => format!("p{k}"),
    };
    let whole = slices.len() == 1;
    if !whole {
        let outs: Vec<String> = (0..slices.len()).map(name).collect();
        let _ = writeln!(
            out,
            "timesplit({}) : [all, {tag}] -> [{}]",
            layout.fractions.join(", "),
            outs.join(", ")
        );
        rules += 1;
    }
    let mut current: Vec<String> = (0..slices.len())
        .map(|k| {
            if whole {
                "all".to_string()
            } else {
                format!("p{k}")
            }
        })
        .collect();
    for (k, s) in slices.iter().enumerate() {
        if let Some(Move {
            ease,
            change: Change::Affine(comps, pivot),
            ..
        }) = &s.play
        {
            let ref_ = if *pivot == Pivot::Local {
                "local"
            } else {
                "world"
            };
            let ease = ease_text(ease).map_or(String::new(), |e| format!(", ease={e}"));
            let _ = writeln!(
                out,
                "animate(affine, {ref_}, {}, {}{ease}) : [{}, {tag}] -> [m{k}]",
                layout.delays[k],
                transform_text(comps, *pivot),
                current[k]
            );
            current[k] = format!("m{k}");
            rules += 1;
        }
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
            let outs: Vec<String> = (0..s.inner.len()).map(|l| format!("p{k}_{l}")).collect();
            let _ = writeln!(
                out,
                "timesplit({}) : [{}, {tag}] -> [{}]",
                fractions.join(", "),
                current[k],
                outs.join(", ")
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
                    format!("p{k}_{l}")
                };
                if let Some(v) = change.opacity {
                    let _ = writeln!(
                        out,
                        "animate(opacity, local, {}, {}{ease}) : [{slice}, {tag}] -> [o{k}_{l}]",
                        delays[l],
                        num(v, 4)
                    );
                    slice = format!("o{k}_{l}");
                    rules += 1;
                }
                if let Some([r, g, b]) = change.fill {
                    let _ = writeln!(
                        out,
                        "animate(fill, local, {}, rgb({}, {}, {}){ease}) : [{slice}, {tag}] -> [f{k}_{l}]",
                        delays[l],
                        num(r * 255.0, 2),
                        num(g * 255.0, 2),
                        num(b * 255.0, 2)
                    );
                    slice = format!("f{k}_{l}");
                    rules += 1;
                }
                leaves[k].push(slice);
            } else {
                leaves[k].push(if one {
                    current[k].clone()
                } else {
                    format!("p{k}_{l}")
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
    /// The written times of `slices` from their lines (layout of [`times_of`]).
    fn of(slices: &[Slice], lines: &[(f64, f64)], duration: f64) -> Times {
        let mut parts = Vec::new();
        let mut delays = Vec::new();
        let mut k = 0;
        let mut prev = (0.0, 0.0);
        for _ in slices {
            let end = lines[k];
            parts.push((end.0 - prev.0) / duration);
            parts.push((end.1 - prev.1) / duration);
            delays.push(linear(lines[k + 1].0, lines[k + 1].1, TIME_DIGITS));
            prev = end;
            k += 2;
        }
        let plain: Vec<f64> = parts.chunks(2).map(|p| p[0]).collect();
        let fractions = if parts.chunks(2).all(|p| num(p[1].abs(), 9) == "0") {
            tidy(&plain)
        } else {
            parts.chunks(2).map(|p| linear(p[0], p[1], 9)).collect()
        };
        let mut inner = Vec::new();
        for (j, s) in slices.iter().enumerate() {
            let mut fr = Vec::new();
            let mut fixed = Vec::new();
            let mut de = Vec::new();
            let start = if j == 0 {
                (0.0, 0.0)
            } else {
                lines[2 * (j - 1)]
            };
            let mut prev = start;
            for _ in &s.inner {
                let end = lines[k];
                let (a, b) = (end.0 - prev.0, end.1 - prev.1);
                fr.push(if b.abs() < 1e-12 && lines[2 * j].1 == start.1 {
                    // A fixed length: its fraction of the fixed parent.
                    let parent = lines[2 * j].0 - start.0;
                    fixed.push(a / parent);
                    num(a / parent, 9)
                } else {
                    format!("({}) / d", linear(a, b, TIME_DIGITS))
                });
                de.push(linear(lines[k + 1].0, lines[k + 1].1, TIME_DIGITS));
                prev = end;
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
