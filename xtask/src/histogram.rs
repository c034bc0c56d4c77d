//! Histogram bins under a rapidly dragged selection (paper sec. 8.1).
//!
//! Two histograms of a synthetic data set with correlated attributes `a` and `b`. A
//! brush on the `a` histogram is dragged back and forth quickly; the `b` histogram shows
//! the points inside the brush. Each brush position is a new target for every `b` bar,
//! so transitions are interrupted at 12 Hz.
//!
//! The paper's point: smooth the *counts*, not the heights. A bar's height is
//! `count × zoom`; the count channel (`sy`, as a fraction of the bar's drawn height) is
//! smoothed, while the y-zoom (`zy`, the same for every bar) is a separate channel with
//! the system `none`, so pinching the axis acts at once while counts keep animating.
//! Bars scale about their bottom centre (`anchors.bar = [0.5, 1]`); the brush follows the
//! pointer exactly (`brush.xy = none`).

use std::fmt::Write as _;

use crate::Example;
use gmotion::signals::SmoothSpec;
use gmotion::transitions::targets::{Attr, Channel, SystemOverride, Target, TargetValue, Targets};

/// Number of bins in each histogram.
pub const BINS: usize = 20;
/// Width of the brush in bins.
pub const BRUSH_BINS: usize = 3;

/// A small deterministic generator (SplitMix64), so the example is the same everywhere.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `n` points `(a, b)` in `[0, 1)²`: `a` uniform, `b = 0.65·a + 0.35·noise` with a
/// bell-shaped noise, so the `b` histogram of a brushed `a` range moves with the brush.
pub fn points(n: usize, seed: u64) -> Vec<(f64, f64)> {
    let mut rng = Rng(seed);
    (0..n)
        .map(|_| {
            let a = rng.next();
            let noise = (rng.next() + rng.next() + rng.next()) / 3.0;
            (a, (0.65 * a + 0.35 * noise).min(0.999_999))
        })
        .collect()
}

/// Counts of `b` per bin for the points whose `a` lies in `[lo, hi)`.
pub fn selection_counts(points: &[(f64, f64)], lo: f64, hi: f64) -> [usize; BINS] {
    let mut counts = [0; BINS];
    for &(a, b) in points {
        if a >= lo && a < hi {
            counts[(b * BINS as f64) as usize] += 1;
        }
    }
    counts
}

/// Counts of `a` per bin.
pub fn a_counts(points: &[(f64, f64)]) -> [usize; BINS] {
    let mut counts = [0; BINS];
    for &(a, _) in points {
        counts[(a * BINS as f64) as usize] += 1;
    }
    counts
}

/// The brush's first bin over time: `(time, bin)` — at rest, then dragged one bin every
/// 1/12 s across the axis and back, then dropped, then moved once more while zoomed.
pub fn brush_path() -> Vec<(f64, usize)> {
    let mut path = vec![(0.0, 4)];
    let mut t = 0.6;
    let sweep: Vec<usize> = (4..=17).chain((0..17).rev()).chain(0..=12).collect();
    for bin in sweep {
        path.push((t, bin));
        t += 1.0 / 12.0;
    }
    path.push((6.3, 8));
    path
}

/// The y-zoom over time: `(time, factor)`.
pub fn zoom_path() -> Vec<(f64, f64)> {
    vec![(0.0, 1.0), (5.2, 2.5), (7.6, 1.0)]
}

// Layout of the picture.
const LEFT: f64 = 40.0;
const RIGHT: f64 = 400.0;
const BASE: f64 = 330.0;
const BIN_W: f64 = 16.0;
const FULL_H: f64 = 230.0;

/// The example: `histogram.svg` and `histogram.targets.json`.
pub fn example() -> Example {
    let pts = points(4000, 7);
    let full = selection_counts(&pts, 0.0, 1.0);
    let a = a_counts(&pts);
    let ref_count = *full.iter().chain(a.iter()).max().unwrap_or(&1) as f64;
    let height = |c: usize| FULL_H * c as f64 / ref_count;

    let mut svg = String::new();
    let _ = writeln!(
        svg,
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="760" height="360" viewBox="0 0 760 360">
  <rect class="background" x="0" y="0" width="760" height="360" fill="#ffffff"/>
  <path class="axis" d="M {} {BASE} H {} M {} {BASE} H {}" stroke="#333333" stroke-width="1.5" fill="none"/>"##,
        LEFT - 4.0,
        LEFT + BIN_W * BINS as f64 + 4.0,
        RIGHT - 4.0,
        RIGHT + BIN_W * BINS as f64 + 4.0
    );
    for (i, &c) in a.iter().enumerate() {
        let _ = writeln!(
            svg,
            r##"  <rect class="abin" x="{}" y="{:.3}" width="{}" height="{:.3}" fill="#b9c4d0"/>"##,
            LEFT + BIN_W * i as f64 + 1.0,
            BASE - height(c),
            BIN_W - 2.0,
            height(c)
        );
    }
    let brush0 = brush_path()[0].1;
    let _ = writeln!(
        svg,
        r##"  <rect class="brush" x="{}" y="{}" width="{}" height="{}" fill="#2f6fdf" fill-opacity="0.25" stroke="#2f6fdf" stroke-width="1.5"/>"##,
        LEFT + BIN_W * brush0 as f64,
        BASE - FULL_H - 10.0,
        BIN_W * BRUSH_BINS as f64,
        FULL_H + 10.0
    );
    for (i, &c) in full.iter().enumerate() {
        // Every bin of the full data is drawn; a bin no point falls in keeps a sliver so
        // that its bar can still be scaled.
        let h = height(c).max(0.5);
        let _ = writeln!(
            svg,
            r##"  <rect class="bar" x="{}" y="{:.3}" width="{}" height="{:.3}" fill="#e07b39"/>"##,
            RIGHT + BIN_W * i as f64 + 1.0,
            BASE - h,
            BIN_W - 2.0,
            h
        );
    }
    svg.push_str("</svg>\n");

    let mut targets = Vec::new();
    let push =
        |targets: &mut Vec<Target>, time: f64, tag: &str, id: Option<usize>, attr: Attr, v: f64| {
            targets.push(Target {
                time,
                tag: tag.into(),
                id,
                attr,
                value: TargetValue::Number(v),
                location: String::new(),
            });
        };
    let mut last = [usize::MAX; BINS];
    for (time, bin) in brush_path() {
        push(
            &mut targets,
            time,
            "brush",
            Some(0),
            Attr::X,
            LEFT + BIN_W * bin as f64,
        );
        let lo = bin as f64 / BINS as f64;
        let counts = selection_counts(&pts, lo, lo + BRUSH_BINS as f64 / BINS as f64);
        for (i, &c) in counts.iter().enumerate() {
            // Only changes are targets; an unchanged count is no news.
            if c != last[i] {
                let drawn = height(full[i]).max(0.5);
                push(
                    &mut targets,
                    time,
                    "bar",
                    Some(i),
                    Attr::Whole(Channel::Sy),
                    height(c) / drawn,
                );
                last[i] = c;
            }
        }
    }
    for (time, z) in zoom_path() {
        push(&mut targets, time, "bar", None, Attr::Whole(Channel::Zy), z);
    }
    let none = SmoothSpec::Identity;
    Example {
        name: "histogram",
        svg,
        targets: Targets {
            system: Some(SmoothSpec::parse("spring(0.45, 0.1)").expect("valid system")),
            systems: vec![
                SystemOverride {
                    tag: None,
                    channel: Channel::Zy,
                    system: none.clone(),
                },
                SystemOverride {
                    tag: Some("brush".into()),
                    channel: Channel::Position,
                    system: none,
                },
            ],
            fps: Some(60.0),
            duration: Some(9.0),
            anchors: vec![("bar".into(), [0.5, 1.0]), ("brush".into(), [0.0, 0.5])],
            targets,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_follow_the_brush() {
        let pts = points(4000, 7);
        let full = selection_counts(&pts, 0.0, 1.0);
        assert_eq!(full.iter().sum::<usize>(), 4000);
        assert!(
            full.iter().all(|&c| c > 0),
            "every bin has points: {full:?}"
        );
        // b correlates with a: a low brush selects low b.
        let low = selection_counts(&pts, 0.0, 0.15);
        let high = selection_counts(&pts, 0.85, 1.0);
        let mean = |c: &[usize; BINS]| {
            c.iter()
                .enumerate()
                .map(|(i, &n)| i as f64 * n as f64)
                .sum::<f64>()
                / c.iter().sum::<usize>() as f64
        };
        assert!(mean(&low) + 5.0 < mean(&high));
    }

    #[test]
    fn the_brush_is_dragged_faster_than_the_bars_settle() {
        let path = brush_path();
        let gaps: Vec<f64> = path.windows(2).map(|w| w[1].0 - w[0].0).collect();
        assert!(gaps.iter().filter(|&&g| g < 0.1).count() > 40);
    }
}
