//! Clip paths and masks as Lottie: layer masks where the clip is a union of simple
//! outlines, else track mattes drawn from the clip or mask content.
//!
//! A track matte is an ordinary Lottie layer whose pixels are used as coverage, so its
//! content is built here as a scene [`Group`] (outlines whitened, the clip's own clip
//! kept) and written by the same walker as the art. That is deliberate, not a shortcut:
//! matte content can hold nested groups, transforms, clips of clips and masks, and a
//! second writer for it would have to repeat every one of those cases; the groups built
//! here are never shown to anything but that walker.

use super::*;

impl Builder<'_> {
    pub(super) fn classify_clip(&self, clip: &ClipPath) -> ClipKind {
        if clip.clip_path.is_some() {
            return ClipKind::Matte;
        }
        let mut out = Vec::new();
        if !collect_clip(&clip.root, clip.transform * clip.root.transform, &mut out) {
            return ClipKind::Matte;
        }
        if out.is_empty() {
            ClipKind::Empty
        } else {
            ClipKind::Masks(out)
        }
    }
}

/// How a clip path can be written.
pub(super) enum ClipKind {
    /// It clips everything away.
    Empty,
    /// As layer masks: closed contours in the clipped group's coordinates.
    Masks(Vec<Contour>),
    /// Only as a track matte.
    Matte,
}

/// Collects clip outlines as mask contours; false when they cannot all be layer masks.
pub(super) fn collect_clip(g: &Group, ts: Affine, out: &mut Vec<Contour>) -> bool {
    for c in &g.children {
        match c {
            Node::Group(h) => {
                if h.clip_path.is_some() || h.mask.is_some() {
                    return false;
                }
                if !collect_clip(h, ts * h.transform, out) {
                    return false;
                }
            }
            Node::Path(p) => {
                let Some(f) = &p.fill else { continue };
                let cs = contours(&p.path);
                match cs.as_slice() {
                    [] => {}
                    [c] if f.rule == FillRule::NonZero => out.push(c.transformed(ts)),
                    _ => return false,
                }
            }
            // SVG clips with shapes only; the importer puts no images in clip paths.
            Node::Image(_) => {}
        }
    }
    true
}

/// A layer mask (mode add) of a contour.
pub(super) fn mask(c: &Contour) -> LMask {
    let mut b: Bezier = c.to_bezier();
    b.closed = Some(true);
    LMask {
        at: Default::default(),
        mode: "a".to_string(),
        pt: Some(Prop::fixed(Value::Bezier(Box::new(b)))),
        o: Some(Prop::scalar(N(100.0))),
        x: Some(Prop::scalar(N(0.0))),
        inverted: false,
    }
}

/// Clip content as an ordinary group: every outline filled opaque white with its clip rule,
/// under the clip's transform; a clip on the clip becomes the group's clip.
pub(super) fn clip_group(clip: &ClipPath) -> Group {
    Group {
        id: clip.id.clone(),
        clip_path: clip.clip_path.clone(),
        children: vec![Node::Group(Group {
            transform: clip.transform * clip.root.transform,
            clip_path: clip.root.clip_path.clone(),
            children: whiten(&clip.root.children),
            ..Group::new()
        })],
        ..Group::new()
    }
}

pub(super) fn whiten(nodes: &[Node]) -> Vec<Node> {
    nodes
        .iter()
        .filter_map(|n| match n {
            Node::Group(g) => Some(Node::Group(Group {
                id: g.id.clone(),
                label: g.label.clone(),
                transform: g.transform,
                opacity: 1.0,
                clip_path: g.clip_path.clone(),
                mask: None,
                filter: None,
                children: whiten(&g.children),
                unit: None,
            })),
            Node::Path(p) => {
                let f = p.fill.as_ref()?;
                let white = Fill {
                    rule: f.rule,
                    ..Fill::solid(Color::WHITE)
                };
                Some(Node::Path(PathNode::new(
                    p.id.clone(),
                    p.path.clone(),
                    Some(white),
                    None,
                )))
            }
            Node::Image(_) => None,
        })
        .collect()
}

pub(super) fn strip_units(nodes: &[Node]) -> Vec<Node> {
    nodes
        .iter()
        .map(|n| match n {
            Node::Group(g) => Node::Group(Group {
                children: strip_units(&g.children),
                unit: None,
                ..g.clone()
            }),
            Node::Path(_) | Node::Image(_) => {
                let mut n = n.clone();
                n.set_unit(None);
                n
            }
        })
        .collect()
}

/// Mask content as a group: clipped to the mask rectangle (and by `clip`), masked by the
/// mask's own mask.
pub(super) fn mask_group(m: &Mask, clip: Option<Arc<ClipPath>>) -> Group {
    Group {
        id: m.id.clone(),
        clip_path: Some(rect_clip(m.rect)),
        children: vec![Node::Group(Group {
            clip_path: clip,
            mask: m.mask.clone(),
            children: vec![Node::Group(Group {
                children: strip_units(&m.root.children),
                ..m.root.clone()
            })],
            ..Group::new()
        })],
        ..Group::new()
    }
}

pub(super) fn rect_clip(r: Rect) -> Arc<ClipPath> {
    Arc::new(ClipPath::rect(r))
}
