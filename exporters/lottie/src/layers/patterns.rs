//! Pattern paints as Lottie: the pattern's tiles as content under an alpha matte of the
//! painted outline.

use super::mattes::{rect_clip, strip_units};
use super::paths::Outline;
use super::*;

impl Builder<'_> {
    /// A pattern paint as a group: the tiles, masked by the painted outline.
    pub(super) fn pattern_group(
        &mut self,
        pat: &Pattern,
        opacity: f32,
        path: &BezPath,
        outline: Outline,
        element: &str,
    ) -> Option<Group> {
        let tile = pat.rect;
        if tile.width() <= 0.0 || tile.height() <= 0.0 || !pat.transform.determinant().is_normal() {
            return None;
        }
        let area = match &outline {
            Outline::Fill(_) => path.bounding_box(),
            Outline::Stroke(s) => path.bounding_box().inflate(s.width, s.width),
        };
        let local = pat.transform.inverse().transform_rect_bbox(area);
        let i0 = ((local.x0 - tile.x0) / tile.width()).floor();
        let i1 = ((local.x1 - tile.x0) / tile.width()).ceil();
        let j0 = ((local.y0 - tile.y0) / tile.height()).floor();
        let j1 = ((local.y1 - tile.y0) / tile.height()).ceil();
        let count = (i1 - i0) * (j1 - j0);
        if !(count.is_finite() && count <= MAX_TILES) {
            self.warnings.push(format!(
                "element `{element}`: pattern `{}` needs {count} tiles, more than Lottie output should hold; painted with its first colour",
                pat.id
            ));
            return None;
        }
        let content_bbox = bounds(&pat.root);
        let overflows = content_bbox.is_none_or(|b| {
            b.x0 < -1e-9
                || b.y0 < -1e-9
                || b.x1 > tile.width() + 1e-9
                || b.y1 > tile.height() + 1e-9
        });
        let tile_clip =
            overflows.then(|| rect_clip(Rect::new(0.0, 0.0, tile.width(), tile.height())));
        let mut tiles = Vec::with_capacity(count as usize);
        for j in j0 as i64..j1 as i64 {
            for i in i0 as i64..i1 as i64 {
                let at = Vec2::new(
                    tile.x0 + i as f64 * tile.width(),
                    tile.y0 + j as f64 * tile.height(),
                );
                tiles.push(Node::Group(Group {
                    transform: Affine::translate(at) * pat.root.transform,
                    clip_path: tile_clip.clone(),
                    children: strip_units(&pat.root.children),
                    ..Group::new()
                }));
            }
        }
        let outline_node = match outline {
            Outline::Fill(f) => {
                let white = Fill {
                    rule: f.rule,
                    ..Fill::solid(Color::WHITE)
                };
                PathNode::new(String::new(), path.clone(), Some(white), None)
            }
            Outline::Stroke(s) => {
                let white = Stroke {
                    paint: Paint::Solid(Color::WHITE),
                    opacity: 1.0,
                    ..s
                };
                PathNode::new(String::new(), path.clone(), None, Some(white))
            }
        };
        let mask = Mask {
            id: format!("{}-outline", pat.id),
            rect: area.inflate(1.0, 1.0),
            kind: MaskKind::Alpha,
            mask: None,
            root: Group {
                children: vec![Node::Path(outline_node)],
                ..Group::new()
            },
        };
        Some(Group {
            id: element.to_string(),
            opacity,
            mask: Some(Arc::new(mask)),
            children: vec![Node::Group(Group {
                transform: pat.transform,
                children: tiles,
                ..Group::new()
            })],
            ..Group::new()
        })
    }
}

/// Most pattern tiles drawn for one paint before falling back to a plain colour.
pub(super) const MAX_TILES: f64 = 2500.0;

/// The bounds of a group's drawing (strokes included) in its own coordinates.
pub(super) fn bounds(g: &Group) -> Option<Rect> {
    let mut out: Option<Rect> = None;
    for c in &g.children {
        let b = match c {
            Node::Group(h) => bounds(h).map(|b| h.transform.transform_rect_bbox(b)),
            Node::Path(p) => {
                let w = p.stroke.as_ref().map_or(0.0, |s| s.width / 2.0 * 1.5);
                Some(p.path.bounding_box().inflate(w, w))
            }
            Node::Image(i) => Some(i.rect()),
        };
        if let Some(b) = b {
            out = Some(out.map_or(b, |o| o.union(b)));
        }
    }
    out
}
