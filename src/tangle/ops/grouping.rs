//! Grouping operators (gTangle sec. 4.1): `ungroup()` gives every shape a group of its own,
//! `regroup(k, mode)` deals a group's shapes into `k` new groups. They change no geometry;
//! they decide which shapes the next rules treat together, which is how tangles get their
//! chessboards, stripes and scattered accents (gTangle Fig. 4).

use crate::tangle::noise::{key, unit};

/// How `regroup` deals shapes into groups.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RegroupMode {
    /// By id within the group: `s mod k` (the paper's definition).
    Id,
    /// By split cell: `(i + j) mod k` — a chessboard on a dual split.
    Chessboard,
    /// By strip along the orientation: `i mod k` — columns.
    Columns,
    /// By strip across the orientation: `j mod k` — rows.
    Rows,
    /// At random (seeded by shape).
    Random,
}

impl RegroupMode {
    /// The mode named by a grammar keyword.
    pub fn from_name(name: &str) -> Option<RegroupMode> {
        Some(match name {
            "id" => RegroupMode::Id,
            "chessboard" => RegroupMode::Chessboard,
            "columns" => RegroupMode::Columns,
            "rows" => RegroupMode::Rows,
            "random" => RegroupMode::Random,
            _ => return None,
        })
    }
}

/// Which of the `k` new groups a shape goes to. `cell` is the shape's split cell, `sid` its
/// id in its group, `seed` the key for random dealing.
pub fn regroup_slot(mode: RegroupMode, k: usize, cell: (i64, i64), sid: usize, seed: u64) -> usize {
    let k = k.max(1);
    let m = |v: i64| v.rem_euclid(k as i64) as usize;
    match mode {
        RegroupMode::Id => sid % k,
        RegroupMode::Chessboard => m(cell.0 + cell.1),
        RegroupMode::Columns => m(cell.0),
        RegroupMode::Rows => m(cell.1),
        RegroupMode::Random => ((unit(key(&[seed, sid as u64])) * k as f64) as usize).min(k - 1),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dealing_patterns() {
        // A 4 × 4 grid dealt into two groups.
        let cells: Vec<(i64, i64)> = (0..4).flat_map(|i| (0..4).map(move |j| (i, j))).collect();
        let deal = |mode| -> Vec<usize> {
            cells
                .iter()
                .enumerate()
                .map(|(s, &c)| regroup_slot(mode, 2, c, s, 7))
                .collect()
        };
        let chess = deal(RegroupMode::Chessboard);
        assert_eq!(&chess[..5], &[0, 1, 0, 1, 1]);
        let cols = deal(RegroupMode::Columns);
        assert_eq!(&cols[..5], &[0, 0, 0, 0, 1]);
        let rows = deal(RegroupMode::Rows);
        assert_eq!(&rows[..5], &[0, 1, 0, 1, 0]);
        let random = deal(RegroupMode::Random);
        assert!(random.contains(&0) && random.contains(&1));
        assert_eq!(random, deal(RegroupMode::Random));
        assert_eq!(
            RegroupMode::from_name("columns"),
            Some(RegroupMode::Columns)
        );
        assert_eq!(RegroupMode::from_name("diagonal"), None);
    }
}
