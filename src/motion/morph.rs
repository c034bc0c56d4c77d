//! The outline channel of a track: shape morphs ([`crate::morph`] matches the outlines).
//!
//! A morph replaces the geometry of a unit's paths (the transform channel still moves the
//! unit on top, so a morph composes with motion as an affine map of the in-between). Like
//! an attribute it replaces rather than composes: a second morph starts from the outline
//! the first ended in, and an inverted twin plays its twin's pair of outlines backwards.

use std::sync::Arc;

use kurbo::BezPath;

use super::Timing;

/// One window of a morph on one shape: the unit's paths, in document order, each in its
/// own coordinates, from one outline to another of the same structure.
#[derive(Clone, Debug)]
pub struct MorphSeg {
    /// Window start (a slice boundary).
    pub t0: f64,
    /// Window end.
    pub t1: f64,
    /// The morph's timing (its whole slice).
    pub timing: Timing,
    /// The outlines at progress 0, one per path of the unit.
    pub from: Arc<[BezPath]>,
    /// The outlines at progress 1, each of the structure of its `from`.
    pub to: Arc<[BezPath]>,
}

impl MorphSeg {
    /// The progress at `t` (clamped to the window).
    pub fn progress(&self, t: f64) -> f64 {
        self.timing.progress(t.clamp(self.t0, self.t1))
    }

    /// The outlines at `t`.
    pub fn outlines_at(&self, t: f64) -> Vec<BezPath> {
        let p = self.progress(t);
        self.from
            .iter()
            .zip(self.to.iter())
            .map(|(a, b)| crate::morph::lerp(a, b, p))
            .collect()
    }
}

/// The outlines of a unit at `t` under `segs` (sorted by `t0`): `None` before the first
/// morph (the drawn paths), else the last window begun, held after it ends.
pub fn outlines_at(segs: &[MorphSeg], t: f64) -> Option<Vec<BezPath>> {
    let i = segs.partition_point(|s| s.t0 <= t);
    (i > 0).then(|| segs[i - 1].outlines_at(t))
}

/// Path `leaf`'s outline at `t` in the one structure all of `segs` share (sorted by `t0`):
/// before the first morph its start (the drawn path, cut as the morphs cut it), so an
/// exporter sampling the outline through time (under per-vertex motion) gets the same
/// points to interpolate at every instant. `None` without morphs or without that path.
pub fn leaf_at(segs: &[MorphSeg], leaf: usize, t: f64) -> Option<BezPath> {
    let (s, p) = match segs.partition_point(|s| s.t0 <= t).checked_sub(1) {
        Some(k) => (&segs[k], segs[k].progress(t)),
        None => (segs.first()?, 0.0),
    };
    Some(crate::morph::lerp(s.from.get(leaf)?, s.to.get(leaf)?, p))
}
