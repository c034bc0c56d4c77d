//! Sampling: every unit's world motion relative to the reference frame, its opacity and
//! its paint, at every frame of the composition, as the player draws them.

use gmotion::scene::{Node, Paint, Scene};
use gmotion_pipeline::LottieSource;
use kurbo::{Affine, BezPath, PathEl, Point};
use rayon::prelude::*;

use crate::LearnError;

/// How many points of a unit's drawing are followed to measure its error in pixels.
const MAX_POINTS: usize = 24;

/// One unit's samples, one entry per frame.
#[derive(Clone, Debug)]
pub struct UnitSamples {
    /// The unit's world motion since the reference frame (`world(f) · world(ref)⁻¹`).
    pub motion: Vec<Affine>,
    /// Its opacity: the product of the opacities of the groups down to it, times its fill's
    /// opacity when it paints one fill colour.
    pub opacity: Vec<f64>,
    /// Its representative solid fill colour, if it has one (RGBA, 0 … 1).
    pub fill: Vec<Option<[f32; 4]>>,
    /// Whether its first solid stroke's colour, opacity or width changes over the frames.
    pub stroke_changes: bool,
    /// Its first solid stroke at every frame (RGB, opacity, width) while it changes (empty
    /// when it holds).
    pub stroke: Vec<Option<[f32; 5]>>,
    /// Points of its drawing at the reference frame, on the canvas.
    pub points: Vec<Point>,
    /// The largest distance, over the frames, between the points as drawn and as the unit's
    /// motion alone carries them: what moves inside the unit (paths, inner layers).
    pub inner_px: f64,
    /// Its centroid at the reference frame (the `local` pivot).
    pub centroid: Point,
    /// Whether all its solid fills have one colour at the reference frame (a fill change
    /// of the grammar tints them all to one colour).
    pub one_fill: bool,
    /// For a unit drawn by one path whose outline changes (a morph, keyed path data): its
    /// path at the reference frame placed on the canvas (`world`), and its outline at every
    /// frame in the path's own coordinates (empty while it has not changed, and for every
    /// other unit). Its motion is then the path's own world transform, so that the motion
    /// and the outline together carry the drawing exactly.
    pub outline: Option<Outline>,
}

/// A one-path unit's outline over the frames ([`UnitSamples::outline`]).
#[derive(Clone, Debug)]
pub struct Outline {
    /// The path's world transform at the reference frame: where a target outline is drawn.
    pub world: Affine,
    /// The path at every frame, in its own coordinates; empty when it never changes.
    pub frames: Vec<BezPath>,
}

/// The most outline points kept over all units and frames (16 bytes each): past it, later
/// units' changing outlines are not recorded (and stay reported as changing inside).
const MAX_OUTLINE_POINTS: usize = 8_000_000;

/// Every unit sampled at every frame of `src`.
pub fn sample(
    src: &LottieSource,
    reference: &Scene,
    max_samples: u64,
) -> Result<Vec<UnitSamples>, LearnError> {
    let doc = &src.document;
    let frames = ((doc.op - doc.ip).ceil().max(1.0)) as usize;
    let units = reference.shapes.len();
    let samples = (frames as u64).saturating_mul(units as u64);
    if samples > max_samples {
        return Err(LearnError::Limit(format!(
            "{units} units × {frames} frames = {samples} samples, more than the limit of {max_samples} (raise it with --limit learn-samples=N)"
        )));
    }
    let ref_world: Vec<Affine> = (0..units).map(|u| world(reference, u)).collect();
    let ref_points: Vec<Vec<Point>> = (0..units).map(|u| points(reference, u)).collect();
    let mut out: Vec<UnitSamples> = reference
        .shapes
        .iter()
        .enumerate()
        .map(|(u, s)| UnitSamples {
            motion: Vec::with_capacity(frames),
            opacity: Vec::with_capacity(frames),
            fill: Vec::with_capacity(frames),
            stroke_changes: false,
            stroke: Vec::new(),
            points: ref_points[u].clone(),
            inner_px: 0.0,
            centroid: s.centroid,
            one_fill: fill_colours(reference, u) <= 1,
            outline: one_path(reference, u).map(|(world, _)| Outline {
                world,
                frames: Vec::new(),
            }),
        })
        .collect();
    let ref_paths: Vec<Option<BezPath>> = (0..units)
        .map(|u| one_path(reference, u).map(|(_, p)| p))
        .collect();
    let mut outline_points = 0usize;
    // Frames are drawn in parallel, a few at a time (a frame of every unit is small; all
    // frames of a large file at once would not be).
    let chunk = rayon::current_num_threads().max(1) * 2;
    // Each unit's stroke at frame 0, what later frames are compared with.
    let mut first_stroke: Vec<Option<[f32; 5]>> = vec![None; units];
    let mut f0 = 0;
    while f0 < frames {
        let f1 = (f0 + chunk).min(frames);
        let drawn: Vec<Result<Vec<Sample>, LearnError>> = (f0..f1)
            .into_par_iter()
            .map(|f| {
                let (scene, _) = src
                    .scene_at(doc.ip + f as f64)
                    .map_err(|e| LearnError::Input(e.to_string()))?;
                Ok((0..units)
                    .map(|u| sample_unit(&scene, u, ref_world[u], &out[u]))
                    .collect())
            })
            .collect();
        for frame in drawn {
            for (u, (s, mut smp)) in out.iter_mut().zip(frame?).enumerate() {
                // A unit seen at frame 0 that later draws nothing is invisible then: it
                // keeps where it was, its paint and its outline, at opacity 0 (what the
                // grammar can say: a fade, not a removal). One absent from frame 0 on
                // would have the still drawn at opacity 0, which no rule raises: it is
                // sampled as drawn.
                if smp.absent && s.opacity.first().is_some_and(|o| *o > 0.0) {
                    smp.motion = s.motion.last().copied().unwrap_or(Affine::IDENTITY);
                    smp.inner_px = 0.0;
                    smp.opacity = 0.0;
                    smp.fill = s.fill.last().copied().flatten();
                    smp.stroke = s.stroke.last().copied().flatten().or(first_stroke[u]);
                    smp.outline = s
                        .outline
                        .as_ref()
                        .and_then(|o| o.frames.last().cloned())
                        .or_else(|| ref_paths[u].clone());
                }
                if f0 == 0 && s.motion.is_empty() {
                    first_stroke[u] = smp.stroke;
                }
                s.inner_px = s.inner_px.max(smp.inner_px);
                let changed = match (first_stroke[u], smp.stroke) {
                    (Some(a), Some(b)) => a.iter().zip(&b).any(|(x, y)| (x - y).abs() > 1e-4),
                    (a, b) => a.is_some() != b.is_some(),
                };
                if changed && !s.stroke_changes {
                    // Kept from the first change on (frames before it held frame 0's).
                    s.stroke = vec![first_stroke[u]; s.motion.len()];
                }
                s.stroke_changes |= changed;
                if s.stroke_changes {
                    s.stroke.push(smp.stroke);
                }
                if let (Some(o), Some(reference)) = (s.outline.as_mut(), &ref_paths[u]) {
                    match smp.outline {
                        Some(now) if !same_structure(&now, reference) => s.outline = None,
                        Some(now) if !o.frames.is_empty() => o.frames.push(now),
                        Some(now) if now != *reference => {
                            let size = now.elements().len() * 3 * frames;
                            if outline_points + size <= MAX_OUTLINE_POINTS {
                                outline_points += size;
                                o.frames = vec![reference.clone(); s.motion.len()];
                                o.frames.push(now);
                            } else {
                                s.outline = None;
                            }
                        }
                        Some(_) => {}
                        // Its structure changed: no outline can be said.
                        None => s.outline = None,
                    }
                }
                s.motion.push(smp.motion);
                s.opacity.push(smp.opacity);
                s.fill.push(smp.fill);
            }
        }
        f0 = f1;
    }
    Ok(out)
}

/// One unit at one frame.
struct Sample {
    motion: Affine,
    inner_px: f64,
    opacity: f64,
    fill: Option<[f32; 4]>,
    stroke: Option<[f32; 5]>,
    /// A one-path unit's path in its own coordinates, when it has the reference's
    /// structure.
    outline: Option<BezPath>,
    /// Whether the unit draws nothing at this frame.
    absent: bool,
}

/// Unit `u` of `scene` (one frame) against its reference-frame world transform `r` and
/// points (in `s`).
fn sample_unit(scene: &Scene, u: usize, r: Affine, s: &UnitSamples) -> Sample {
    let w = world(scene, u);
    let m = if r.determinant().abs() < 1e-12 {
        Affine::IDENTITY
    } else {
        w * r.inverse()
    };
    let now = points(scene, u);
    // A one-path unit moves with its path's own world transform (an exporter may turn a
    // group inside the layer), whatever its outline does.
    let path = s.outline.as_ref().and_then(|o| {
        let (world, path) = one_path(scene, u)?;
        (o.world.determinant().abs() >= 1e-12).then(|| (world * o.world.inverse(), path))
    });
    let m = path.as_ref().map_or(m, |(m, _)| *m);
    let (m, inner_px) = if now.len() == s.points.len() {
        // The motion may live inside the layer (a group's transform): when the layer's
        // own does not carry the drawing, the affine that best does.
        let off = |m: Affine| {
            s.points
                .iter()
                .zip(&now)
                .map(|(p, q)| (m * *p - *q).hypot())
                .fold(0.0, f64::max)
        };
        let m = match best_affine(&s.points, &now) {
            Some(fit) if path.is_none() && off(m) > 1e-3 && off(fit) < off(m) => fit,
            _ => m,
        };
        (m, off(m))
    } else {
        (m, f64::INFINITY)
    };
    // A unit that draws nothing at this frame (its layer out of its time, or faded out)
    // is as if drawn at opacity 0; the merge keeps the rest of its state.
    let absent = now.is_empty() && !s.points.is_empty();
    let fill = fill(scene, u);
    // A one-colour unit's fill opacity is part of how opaque it is drawn (an exporter may
    // write an opacity change there rather than on the layer).
    let fill_opacity = match (s.one_fill, fill) {
        (true, Some(c)) => f64::from(c[3]),
        _ => 1.0,
    };
    Sample {
        motion: m,
        inner_px,
        opacity: opacity(scene, u) * fill_opacity,
        fill,
        stroke: stroke(scene, u),
        outline: path.map(|(_, p)| p),
        absent,
    }
}

/// Whether two paths have the same elements, one for one (a morph between them moves
/// each point straight to its partner, as path keyframes interpolate).
fn same_structure(a: &BezPath, b: &BezPath) -> bool {
    a.elements().len() == b.elements().len()
        && a.elements()
            .iter()
            .zip(b.elements())
            .all(|(x, y)| std::mem::discriminant(x) == std::mem::discriminant(y))
}

/// When unit `u` draws one path (and no image): that path's world transform and its
/// outline in its own coordinates.
fn one_path(scene: &Scene, u: usize) -> Option<(Affine, BezPath)> {
    fn find<'a>(n: &'a Node, m: Affine, out: &mut Vec<(Affine, &'a BezPath)>) -> bool {
        match n {
            Node::Path(p) => {
                out.push((m, &p.path));
                true
            }
            Node::Group(g) => g.children.iter().all(|c| find(c, m * g.transform, out)),
            Node::Image(_) => false,
        }
    }
    let nodes = chain(scene, u);
    let (last, above) = nodes.split_last()?;
    let mut m = scene.root.transform;
    for n in above {
        if let Node::Group(g) = n {
            m *= g.transform;
        }
    }
    let mut found = Vec::new();
    if !find(last, m, &mut found) || found.len() != 1 {
        return None;
    }
    let (world, path) = found[0];
    Some((world, cubic_form(path)))
}

/// `path` with every segment a cubic, a line's control points on its ends: a Lottie path
/// writes a corner as a vertex without tangents, which the player draws as a line, and
/// interpolates between keys as a cubic whose tangents grow from nothing; so its frames
/// keep one structure, and a morph between two of them moves the same points.
fn cubic_form(path: &BezPath) -> BezPath {
    let mut out = BezPath::new();
    let mut at = Point::ORIGIN;
    for el in path.elements() {
        match *el {
            PathEl::MoveTo(p) => {
                out.move_to(p);
                at = p;
            }
            PathEl::LineTo(p) => {
                out.curve_to(at, p, p);
                at = p;
            }
            PathEl::QuadTo(q, p) => {
                out.curve_to(at + (q - at) * (2.0 / 3.0), p + (q - p) * (2.0 / 3.0), p);
                at = p;
            }
            PathEl::CurveTo(a, b, p) => {
                out.curve_to(a, b, p);
                at = p;
            }
            PathEl::ClosePath => out.close_path(),
        }
    }
    out
}

/// The nodes from the root down to unit `u`'s node, the unit's own last.
fn chain(scene: &Scene, u: usize) -> Vec<&Node> {
    let mut out = Vec::new();
    let path = &scene.shapes[u].node_path;
    for i in 1..=path.len() {
        if let Some(n) = scene.root.node_at(&path[..i]) {
            out.push(n);
        }
    }
    out
}

/// Unit `u`'s world transform: the groups' transforms from the root down to it, its own
/// included.
fn world(scene: &Scene, u: usize) -> Affine {
    let mut m = scene.root.transform;
    for n in chain(scene, u) {
        if let Node::Group(g) = n {
            m *= g.transform;
        }
    }
    m
}

/// Unit `u`'s opacity as its first path is drawn: the product of the opacities of the
/// groups down to that path (an exporter may fade a group inside the unit's layer).
fn opacity(scene: &Scene, u: usize) -> f64 {
    let mut o = f64::from(scene.root.opacity);
    let nodes = chain(scene, u);
    for n in &nodes {
        if let Node::Group(g) = n {
            o *= f64::from(g.opacity);
        }
    }
    // Below the unit's node, down to its first path.
    let mut at = nodes.last().copied();
    while let Some(Node::Group(g)) = at {
        at = g.children.iter().find(|c| has_path(c));
        if let Some(Node::Group(inner)) = at {
            o *= f64::from(inner.opacity);
        }
    }
    o
}

/// Whether `n` draws a path.
fn has_path(n: &Node) -> bool {
    match n {
        Node::Path(_) => true,
        Node::Group(g) => g.children.iter().any(has_path),
        Node::Image(_) => false,
    }
}

/// Sets the opacity of the groups from unit `node` down to its first path to 1, and
/// what the still scene moves onto the unit's own opacity.
pub fn clear_route_opacity(node: &mut Node) {
    let mut at = Some(node);
    while let Some(Node::Group(g)) = at {
        g.opacity = 1.0;
        at = g.children.iter_mut().find(|c| has_path(c));
    }
}

/// Whether a path's fill covers anything: a fill on an outline of no area (a line, as
/// an exporter may keep a stroke's centre line beside its outlined stroke) paints nothing,
/// so its colour is not the unit's.
fn fills_area(p: &gmotion::scene::PathNode) -> bool {
    use kurbo::Shape as _;
    // Each subpath closed, as a fill closes it.
    let mut closed = BezPath::new();
    for el in p.path.elements() {
        if matches!(el, PathEl::MoveTo(_))
            && !matches!(closed.elements().last(), None | Some(PathEl::ClosePath))
        {
            closed.close_path();
        }
        closed.push(*el);
    }
    if !matches!(closed.elements().last(), None | Some(PathEl::ClosePath)) {
        closed.close_path();
    }
    p.fill.is_some() && closed.area().abs() > 1e-9
}

/// Unit `u`'s first solid fill colour (of a path whose fill covers anything).
fn fill(scene: &Scene, u: usize) -> Option<[f32; 4]> {
    fn first(n: &Node) -> Option<[f32; 4]> {
        match n {
            Node::Path(p) if !fills_area(p) => None,
            Node::Path(p) => match p.fill.as_ref().map(|f| (&f.paint, f.opacity)) {
                Some((Paint::Solid(c), o)) => Some([c.r, c.g, c.b, o]),
                _ => None,
            },
            Node::Group(g) => g.children.iter().find_map(first),
            Node::Image(_) => None,
        }
    }
    chain(scene, u).last().and_then(|n| first(n))
}

/// Unit `u`'s first solid stroke: colour, opacity and width.
fn stroke(scene: &Scene, u: usize) -> Option<[f32; 5]> {
    fn first(n: &Node) -> Option<[f32; 5]> {
        match n {
            Node::Path(p) => match p.stroke.as_ref() {
                Some(st) => match &st.paint {
                    Paint::Solid(c) => Some([c.r, c.g, c.b, st.opacity, st.width as f32]),
                    _ => None,
                },
                None => None,
            },
            Node::Group(g) => g.children.iter().find_map(first),
            Node::Image(_) => None,
        }
    }
    chain(scene, u).last().and_then(|n| first(n))
}

/// How many different solid fill colours unit `u` paints (gradients count as two).
fn fill_colours(scene: &Scene, u: usize) -> usize {
    fn visit(n: &Node, out: &mut Vec<[u32; 3]>) {
        match n {
            Node::Path(p) if !fills_area(p) => {}
            Node::Path(p) => match p.fill.as_ref().map(|f| &f.paint) {
                Some(Paint::Solid(c)) => {
                    let key = [c.r.to_bits(), c.g.to_bits(), c.b.to_bits()];
                    if !out.contains(&key) {
                        out.push(key);
                    }
                }
                Some(_) => out.extend([[u32::MAX; 3], [0; 3]]),
                None => {}
            },
            Node::Group(g) => g.children.iter().for_each(|c| visit(c, out)),
            Node::Image(_) => {}
        }
    }
    let mut out = Vec::new();
    if let Some(n) = chain(scene, u).last() {
        visit(n, &mut out);
    }
    out.len()
}

/// Up to [`MAX_POINTS`] on-curve points of unit `u`'s drawing, on the canvas, spread over
/// all its paths (the same points at every frame: the tree keeps its shape).
fn points(scene: &Scene, u: usize) -> Vec<Point> {
    fn collect(n: &Node, m: Affine, out: &mut Vec<Point>) {
        match n {
            Node::Path(p) => {
                for el in p.path.elements() {
                    match *el {
                        PathEl::MoveTo(q)
                        | PathEl::LineTo(q)
                        | PathEl::QuadTo(_, q)
                        | PathEl::CurveTo(_, _, q) => out.push(m * q),
                        PathEl::ClosePath => {}
                    }
                }
            }
            Node::Group(g) => {
                let m = m * g.transform;
                for c in &g.children {
                    collect(c, m, out);
                }
            }
            Node::Image(i) => {
                let r = i.rect();
                out.extend([m * Point::new(r.x0, r.y0), m * Point::new(r.x1, r.y1)]);
            }
        }
    }
    let nodes = chain(scene, u);
    let Some(last) = nodes.last() else {
        return Vec::new();
    };
    // The transform above the unit's own node.
    let mut m = scene.root.transform;
    for n in &nodes[..nodes.len() - 1] {
        if let Node::Group(g) = n {
            m *= g.transform;
        }
    }
    let mut all = Vec::new();
    collect(last, m, &mut all);
    if all.len() <= MAX_POINTS {
        return all;
    }
    let step = all.len() as f64 / MAX_POINTS as f64;
    (0..MAX_POINTS)
        .map(|i| all[(i as f64 * step) as usize])
        .collect()
}

/// The affine map taking `from` onto `to` with the least squared error, when the points
/// span the plane.
fn best_affine(from: &[Point], to: &[Point]) -> Option<Affine> {
    // Normal equations of [x y 1]·(a, c, e) = x' (and likewise for y'), centred for
    // conditioning.
    let n = from.len() as f64;
    if from.len() < 3 {
        return None;
    }
    let c = from.iter().fold(kurbo::Vec2::ZERO, |a, p| a + p.to_vec2()) / n;
    let d = to.iter().fold(kurbo::Vec2::ZERO, |a, p| a + p.to_vec2()) / n;
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    let (mut ux, mut uy, mut vx, mut vy) = (0.0, 0.0, 0.0, 0.0);
    for (p, q) in from.iter().zip(to) {
        let (x, y) = (p.x - c.x, p.y - c.y);
        let (qx, qy) = (q.x - d.x, q.y - d.y);
        sxx += x * x;
        sxy += x * y;
        syy += y * y;
        ux += x * qx;
        uy += y * qx;
        vx += x * qy;
        vy += y * qy;
    }
    let det = sxx * syy - sxy * sxy;
    if det.abs() <= 1e-9 * (sxx * syy).max(1e-12) {
        return None;
    }
    let a = (ux * syy - uy * sxy) / det;
    let cc = (uy * sxx - ux * sxy) / det;
    let b = (vx * syy - vy * sxy) / det;
    let dd = (vy * sxx - vx * sxy) / det;
    // q − d = L (p − c)  ⇒  q = L p + (d − L c).
    let e = d.x - (a * c.x + cc * c.y);
    let f = d.y - (b * c.x + dd * c.y);
    Some(Affine::new([a, b, cc, dd, e, f]))
}
