//! Animating permutations along elliptical arcs (paper sec. 8.2).
//!
//! Items in a row swap places; each moves along half an ellipse whose width is its
//! displacement, at constant speed along the arc (arc length from the incomplete
//! elliptic integral of the second kind, inverted numerically), eased by a four-pole
//! cascade. The system is the matrix FIR `arc(aspect, duration)`: items moving right
//! arc up, items moving left arc down, so they pass without colliding. Some permutations
//! come in quick succession, interrupting the arcs in flight; the FIR sums the partial
//! arcs, so the items still move smoothly.

use std::fmt::Write as _;

use crate::Example;
use gmotion::signals::SmoothSpec;
use gmotion::transitions::targets::{Attr, Target, TargetValue, Targets};

/// Number of items.
pub const ITEMS: usize = 12;
const SLOT0: f64 = 60.0;
const SLOT_W: f64 = 52.0;
const ROW_Y: f64 = 180.0;

/// The x of slot `i`.
pub fn slot_x(i: usize) -> f64 {
    SLOT0 + SLOT_W * i as f64
}

/// A deterministic shuffle of `0..n` (Fisher–Yates on a linear congruential stream).
pub fn shuffle(n: usize, seed: u64) -> Vec<usize> {
    let mut state = seed
        .wrapping_mul(6_364_136_223_846_793_005)
        .wrapping_add(1_442_695_040_888_963_407);
    let mut p: Vec<usize> = (0..n).collect();
    for i in (1..n).rev() {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let j = ((state >> 33) % (i as u64 + 1)) as usize;
        p.swap(i, j);
    }
    p
}

/// The permutations over time: `(time, slot of each item)`.
pub fn schedule() -> Vec<(f64, Vec<usize>)> {
    let identity: Vec<usize> = (0..ITEMS).collect();
    let reversed: Vec<usize> = (0..ITEMS).rev().collect();
    vec![
        (0.0, identity.clone()),
        (0.4, shuffle(ITEMS, 1)),
        (2.2, reversed),
        // Three permutations in quick succession: each interrupts the arcs in flight.
        (4.0, shuffle(ITEMS, 2)),
        (4.3, shuffle(ITEMS, 3)),
        (4.6, shuffle(ITEMS, 4)),
        (6.6, identity),
    ]
}

/// The example: `permutation.svg` and `permutation.targets.json`.
pub fn example() -> Example {
    let mut svg = String::new();
    let _ = writeln!(
        svg,
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="720" height="360" viewBox="0 0 720 360">
  <rect class="background" x="0" y="0" width="720" height="360" fill="#ffffff"/>"##
    );
    for i in 0..ITEMS {
        let _ = writeln!(
            svg,
            r##"  <rect class="slot" x="{}" y="{}" width="24" height="3" fill="#cccccc"/>"##,
            slot_x(i) - 12.0,
            ROW_Y + 22.0
        );
    }
    for i in 0..ITEMS {
        // Hues around the wheel, so the order is readable at a glance.
        let hue = 360.0 * i as f64 / ITEMS as f64;
        let _ = writeln!(
            svg,
            r##"  <circle class="item" cx="{}" cy="{ROW_Y}" r="16" fill="hsl({hue:.0}, 65%, 55%)" stroke="#333333" stroke-width="1.5"/>"##,
            slot_x(i)
        );
    }
    svg.push_str("</svg>\n");

    let mut targets = Vec::new();
    for (time, perm) in schedule() {
        for (item, &slot) in perm.iter().enumerate() {
            targets.push(Target {
                time,
                tag: "item".into(),
                id: Some(item),
                attr: Attr::X,
                value: TargetValue::Number(slot_x(slot)),
                location: String::new(),
            });
        }
    }
    Example {
        name: "permutation",
        svg,
        targets: Targets {
            system: Some(SmoothSpec::parse("arc(0.6, 1.2)").expect("valid system")),
            systems: Vec::new(),
            fps: Some(60.0),
            duration: Some(8.5),
            anchors: Vec::new(),
            targets,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shuffles_are_permutations() {
        for seed in 0..10 {
            let mut p = shuffle(ITEMS, seed);
            p.sort_unstable();
            assert_eq!(p, (0..ITEMS).collect::<Vec<_>>());
        }
        assert_ne!(shuffle(ITEMS, 1), shuffle(ITEMS, 2));
    }
}
