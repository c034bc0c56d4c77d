//! Clips a unit carries that the still must not keep.
//!
//! A Lottie precomposition clips its content to its own rectangle, and a unit that is a
//! precomposition layer carries that clip inside its group. When what moves is the
//! content inside the precomposition (its inner layers' keyframes) while the layer itself
//! stays, the clip stays where it is in the animation; but the learned motion moves the
//! whole unit, clip and all, so content that enters the precomposition's rectangle from
//! outside would be cut away as it arrives (rlottie's `square_wheel`: a square rolling in
//! from the left of a precomposition the size of the canvas never showed). A rectangle
//! that holds the whole canvas cuts nothing the canvas does not, so the still drops it;
//! the precompositions After Effects makes are mostly the composition's size. (Where the
//! precomposition layer itself moves, its rectangle moves too and may uncover less of
//! the canvas at other frames than at the reference one; content it cut there shows in
//! the learned animation, and the report's error, measured on outlines, does not see it.)

use kurbo::{Affine, Rect, Shape as _};

use gmotion::scene::{Group, Node, Scene};

/// Drops the clips inside unit `u`'s node that are rectangles holding the whole canvas.
pub fn drop_canvas_clips(still: &mut Scene, u: usize) {
    let canvas = Rect::new(0.0, 0.0, still.width, still.height);
    let to_canvas = still.shapes[u].parent_transform;
    let path = still.shapes[u].node_path.clone();
    if let Some(node) = still.root.node_at_mut(&path) {
        drop_in(node, to_canvas, canvas);
    }
}

fn drop_in(node: &mut Node, to_canvas: Affine, canvas: Rect) {
    let Node::Group(g) = node else {
        return;
    };
    let inner = to_canvas * g.transform;
    if holds_canvas(g, inner, canvas) {
        g.clip_path = None;
    }
    for child in &mut g.children {
        drop_in(child, inner, canvas);
    }
}

/// Whether `g`'s clip is one rectangle, upright on the canvas, holding all of it.
fn holds_canvas(g: &Group, inner: Affine, canvas: Rect) -> bool {
    let Some(clip) = g.clip_path.as_deref() else {
        return false;
    };
    if clip.clip_path.is_some() || clip.root.clip_path.is_some() || clip.root.mask.is_some() {
        return false;
    }
    let [Node::Path(p)] = clip.root.children.as_slice() else {
        return false;
    };
    let outline = (inner * clip.transform * clip.root.transform) * p.path.clone();
    let bounds = outline.bounding_box();
    // A rectangle fills its bounding box: its area is the box's (an upright rectangle).
    let upright = (outline.area().abs() - bounds.area()).abs() <= 1e-6 * bounds.area().max(1.0);
    upright && bounds.contains_rect(canvas)
}
