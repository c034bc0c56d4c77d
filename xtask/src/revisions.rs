//! A text document's revision history (paper sec. 8.3, Fig. 5 and 6).
//!
//! Every character that ever exists is one shape. A slider picks the revision shown;
//! each pick is a new target for every character: its position, its size (1 when
//! present, 0 when not) and its colour (blue while it grows in, red as it shrinks away,
//! black otherwise). Dragging the slider quickly interrupts these transitions.
//!
//! Characters that are not present need a position too. The paper orders all characters
//! of the history totally: `cᵢ < cⱼ` if both are present at some revision with `cᵢ`
//! first; characters never present together are ordered by insertion time (earlier
//! first). A hidden character then sits at the position of the least present character
//! after it, or at the end of the line (an always-present end-of-file character).
//!
//! The order is built as a weave: each revision is diffed against the previous one (a
//! longest common subsequence of words and spaces, so a replaced word is deleted and
//! inserted whole), and inserted characters go just before the next kept character —
//! after any deleted ones there, which were inserted earlier. (The figure's caption
//! orders new text *before* deleted text at the same place; the definition in the text,
//! followed here, orders it after.)

use std::fmt::Write as _;

use crate::{Example, ExampleError};
use gmotion::color::Color;
use gmotion::signals::SmoothSpec;
use gmotion::transitions::targets::{Attr, Channel, SystemOverride, Target, TargetValue, Targets};

/// The revisions of Fig. 5.
pub const REVISIONS: [&str; 5] = [
    "the fox",
    "the quick brown fox jumped over the lazy dog",
    "the fox jumped over the dog",
    "the fox jumped over the goat",
    "the gray fox jumped over the happy goat",
];

/// The history in total order: each character with its presence per revision.
#[derive(Clone, Debug, PartialEq)]
pub struct History {
    /// Characters in the total order.
    pub chars: Vec<char>,
    /// `present[r][i]`: character `i` is in revision `r`.
    pub present: Vec<Vec<bool>>,
    /// `index[r]`: the characters of revision `r` in reading order (indices into `chars`).
    pub index: Vec<Vec<usize>>,
}

/// Splits text into words and single non-word characters.
fn tokens(text: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for c in text.chars() {
        match out.last_mut() {
            Some(w) if c.is_alphanumeric() && w.chars().all(char::is_alphanumeric) => w.push(c),
            _ => out.push(c.to_string()),
        }
    }
    out
}

/// Pairs of equal tokens `(i in a, j in b)` of a longest common subsequence.
fn lcs(a: &[String], b: &[String]) -> Vec<(usize, usize)> {
    let (n, m) = (a.len(), b.len());
    let mut len = vec![vec![0usize; m + 1]; n + 1];
    for i in (0..n).rev() {
        for j in (0..m).rev() {
            len[i][j] = if a[i] == b[j] {
                len[i + 1][j + 1] + 1
            } else {
                len[i + 1][j].max(len[i][j + 1])
            };
        }
    }
    let (mut i, mut j, mut out) = (0, 0, Vec::new());
    while i < n && j < m {
        if a[i] == b[j] {
            out.push((i, j));
            i += 1;
            j += 1;
        } else if len[i + 1][j] >= len[i][j + 1] {
            i += 1;
        } else {
            j += 1;
        }
    }
    out
}

/// Builds the total order of the characters of `revisions` (see the module docs).
pub fn history(revisions: &[&str]) -> History {
    // The weave holds character ids; `chars[id]` is the character.
    let mut chars: Vec<char> = Vec::new();
    let mut weave: Vec<usize> = Vec::new();
    let mut index: Vec<Vec<usize>> = Vec::new();
    let mut prev_tokens: Vec<String> = Vec::new();
    let mut prev_ids: Vec<Vec<usize>> = Vec::new();
    for text in revisions {
        let toks = tokens(text);
        let matched = lcs(&prev_tokens, &toks);
        let mut ids: Vec<Option<Vec<usize>>> = vec![None; toks.len()];
        for &(i, j) in &matched {
            ids[j] = Some(prev_ids[i].clone());
        }
        // Insert new tokens' characters just before the next kept character.
        for j in 0..toks.len() {
            if ids[j].is_some() {
                continue;
            }
            let next_kept = ids[j + 1..].iter().flatten().next().map(|v| v[0]);
            let at = next_kept
                .and_then(|id| weave.iter().position(|&w| w == id))
                .unwrap_or(weave.len());
            let new: Vec<usize> = toks[j]
                .chars()
                .map(|c| {
                    chars.push(c);
                    chars.len() - 1
                })
                .collect();
            weave.splice(at..at, new.iter().copied());
            ids[j] = Some(new);
        }
        let ids: Vec<Vec<usize>> = ids.into_iter().flatten().collect();
        index.push(ids.iter().flatten().copied().collect());
        prev_tokens = toks;
        prev_ids = ids;
    }
    // Renumber by weave position.
    let mut pos = vec![0; chars.len()];
    for (p, &id) in weave.iter().enumerate() {
        pos[id] = p;
    }
    let ordered: Vec<char> = weave.iter().map(|&id| chars[id]).collect();
    let index: Vec<Vec<usize>> = index
        .into_iter()
        .map(|r| r.into_iter().map(|id| pos[id]).collect())
        .collect();
    let present = index
        .iter()
        .map(|r| {
            let mut p = vec![false; ordered.len()];
            for &i in r {
                p[i] = true;
            }
            p
        })
        .collect();
    History {
        chars: ordered,
        present,
        index,
    }
}

impl History {
    /// The column of every character in revision `r`: its place in the line when
    /// present, else the column of the least present character after it in the total
    /// order (the end of the line if there is none).
    pub fn columns(&self, r: usize) -> Vec<usize> {
        let mut col = vec![0; self.chars.len()];
        for (k, &i) in self.index[r].iter().enumerate() {
            col[i] = k;
        }
        let mut next = self.index[r].len();
        for i in (0..self.chars.len()).rev() {
            if self.present[r][i] {
                next = col[i];
            } else {
                col[i] = next;
            }
        }
        col
    }
}

/// The slider over time: `(time, revision)` — a slow pass through the history, then a
/// quick drag back to the start and forward again.
pub fn slider() -> Vec<(f64, usize)> {
    let mut s = vec![(0.0, 0), (0.6, 1), (2.2, 2), (3.8, 3), (5.4, 4)];
    let mut t = 7.0;
    for r in [3, 2, 1, 0, 1, 2, 3, 4] {
        s.push((t, r));
        t += 0.15;
    }
    s
}

const FONT_SIZE: f64 = 22.0;
const MARGIN: f64 = 24.0;
const BASELINE: f64 = 70.0;
const BLUE: &str = "#1f5fd6";
const RED: &str = "#d62828";
/// How long a new character stays blue before turning black.
const BLUE_HOLD: f64 = 0.5;

/// The example: `revisions.svg` (every character of the history in total order, as
/// outlines of DejaVu Sans Mono, spaces drawn as `_`) and `revisions.targets.json`.
/// Fails when no monospace font is installed to outline the glyphs with.
pub fn example() -> Result<Example, ExampleError> {
    let h = history(&REVISIONS);
    let (glyphs, advance) = outline_glyphs(&h.chars)?;
    let width = MARGIN * 2.0 + advance * h.chars.len() as f64;
    let mut svg = String::new();
    let _ = writeln!(
        svg,
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="110" viewBox="0 0 {width:.0} 110">
  <rect class="background" x="0" y="0" width="{width:.0}" height="110" fill="#ffffff"/>"##
    );
    for (i, d) in glyphs.iter().enumerate() {
        let fill = if h.chars[i] == ' ' {
            "#9a9a9a"
        } else {
            "#000000"
        };
        let _ = writeln!(svg, r##"  <path class="char" d="{d}" fill="{fill}"/>"##);
    }
    svg.push_str("</svg>\n");

    let base_x = |i: usize| MARGIN + advance * i as f64;
    let mut targets = Vec::new();
    let mut push = |time: f64, i: usize, attr: Attr, value: TargetValue| {
        targets.push(Target {
            time,
            tag: "char".into(),
            id: Some(i),
            attr,
            value,
            location: String::new(),
        });
    };
    let blue = Color::parse(BLUE).expect("colour");
    let red = Color::parse(RED).expect("colour");
    let grey = Color::parse("#9a9a9a").expect("colour");
    let slider = slider();
    let mut last_dx: Vec<Option<f64>> = vec![None; h.chars.len()];
    for (k, &(time, r)) in slider.iter().enumerate() {
        let cols = h.columns(r);
        let prev = if k == 0 { None } else { Some(slider[k - 1].1) };
        for i in 0..h.chars.len() {
            // When the character next disappears, if it does.
            let gone = slider[k + 1..]
                .iter()
                .find(|s| !h.present[s.1][i])
                .map_or(f64::INFINITY, |s| s.0);
            let dx = MARGIN + advance * cols[i] as f64 - base_x(i);
            if last_dx[i] != Some(dx) {
                push(time, i, Attr::Dx, TargetValue::Number(dx));
                last_dx[i] = Some(dx);
            }
            let now = h.present[r][i];
            let before = prev.map(|p| h.present[p][i]);
            if before != Some(now) {
                push(
                    time,
                    i,
                    Attr::Whole(Channel::Scale),
                    TargetValue::Number(if now { 1.0 } else { 0.0 }),
                );
            }
            let rest = if h.chars[i] == ' ' {
                grey
            } else {
                Color::BLACK
            };
            match (before, now) {
                (Some(false), true) => {
                    push(
                        time,
                        i,
                        Attr::Whole(Channel::Fill),
                        TargetValue::Color(blue),
                    );
                    if time + BLUE_HOLD < gone {
                        push(
                            time + BLUE_HOLD,
                            i,
                            Attr::Whole(Channel::Fill),
                            TargetValue::Color(rest),
                        );
                    }
                }
                (Some(true), false) => {
                    push(time, i, Attr::Whole(Channel::Fill), TargetValue::Color(red))
                }
                (None, _) => push(
                    time,
                    i,
                    Attr::Whole(Channel::Fill),
                    TargetValue::Color(rest),
                ),
                _ => {}
            }
        }
    }
    Ok(Example {
        name: "revisions",
        svg,
        targets: Targets {
            system: Some(SmoothSpec::parse("spring(0.5, 0)").expect("valid system")),
            systems: vec![SystemOverride {
                tag: None,
                channel: Channel::Fill,
                system: SmoothSpec::parse("fir(bspline(3), 0.35)").expect("valid system"),
            }],
            fps: Some(60.0),
            duration: Some(10.0),
            anchors: Vec::new(),
            targets,
        },
    })
}

/// Outlines of `chars` (spaces as `_`) laid out in one monospace line, as path data in
/// canvas coordinates, and the advance width. Uses usvg with the system fonts.
fn outline_glyphs(chars: &[char]) -> Result<(Vec<String>, f64), ExampleError> {
    let mut opt = usvg::Options::default();
    opt.fontdb_mut().load_system_fonts();
    let fail = |message: String| ExampleError {
        file: "revisions.svg",
        message,
    };
    // DejaVu Sans Mono advances 0.602 em; measure rather than trust it.
    let probe = |text: &str| -> Result<usvg::Tree, ExampleError> {
        let src = format!(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="2000" height="100"><text x="0" y="{BASELINE}" font-family="DejaVu Sans Mono, monospace" font-size="{FONT_SIZE}">{text}</text></svg>"#
        );
        usvg::Tree::from_str(&src, &opt).map_err(|e| fail(format!("cannot lay out glyphs: {e}")))
    };
    let wide = probe("MMMMMMMMMM")?;
    let bbox = wide.root().abs_bounding_box();
    if bbox.width() <= 0.0 {
        return Err(fail(
            "no monospace font found to outline the characters (install fonts-dejavu)".into(),
        ));
    }
    let advance = f64::from(bbox.width()) / 10.0 * 1.0;
    let mut out = Vec::with_capacity(chars.len());
    for (i, &c) in chars.iter().enumerate() {
        let shown = if c == ' ' { '_' } else { c };
        let tree = probe(&shown.to_string())?;
        let mut d = String::new();
        collect_paths(tree.root(), MARGIN + advance * i as f64, &mut d);
        if d.is_empty() {
            return Err(fail(format!("the font has no outline for `{shown}`")));
        }
        out.push(d);
    }
    Ok((out, advance))
}

fn collect_paths(group: &usvg::Group, dx: f64, d: &mut String) {
    for node in group.children() {
        match node {
            usvg::Node::Group(g) => collect_paths(g, dx, d),
            usvg::Node::Text(t) => collect_paths(t.flattened(), dx, d),
            usvg::Node::Path(p) => {
                let ts = p.abs_transform();
                let map = |pt: usvg::tiny_skia_path::Point| {
                    let mut q = pt;
                    ts.map_point(&mut q);
                    (f64::from(q.x) + dx, f64::from(q.y))
                };
                for seg in p.data().segments() {
                    use usvg::tiny_skia_path::PathSegment as S;
                    let _ = match seg {
                        S::MoveTo(a) => {
                            let (x, y) = map(a);
                            write!(d, "M{x:.2} {y:.2}")
                        }
                        S::LineTo(a) => {
                            let (x, y) = map(a);
                            write!(d, "L{x:.2} {y:.2}")
                        }
                        S::QuadTo(a, b) => {
                            let ((x1, y1), (x, y)) = (map(a), map(b));
                            write!(d, "Q{x1:.2} {y1:.2} {x:.2} {y:.2}")
                        }
                        S::CubicTo(a, b, c) => {
                            let ((x1, y1), (x2, y2), (x, y)) = (map(a), map(b), map(c));
                            write!(d, "C{x1:.2} {y1:.2} {x2:.2} {y2:.2} {x:.2} {y:.2}")
                        }
                        S::Close => write!(d, "Z"),
                    };
                }
            }
            usvg::Node::Image(_) => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn history_orders_all_characters() {
        let h = history(&REVISIONS);
        // Each revision reads back in order.
        for (r, text) in REVISIONS.iter().enumerate() {
            let s: String = h.index[r].iter().map(|&i| h.chars[i]).collect();
            assert_eq!(&s, text);
            // Present characters appear in increasing total order (the partial order holds).
            assert!(h.index[r].windows(2).all(|w| w[0] < w[1]), "revision {r}");
        }
        // "dog" and "goat" are never present together; dog was inserted first.
        let text: String = h.chars.iter().collect();
        let dog = text.find("dog").unwrap();
        let goat = text.find("goat").unwrap();
        assert!(dog < goat, "{text}");
        // Replacing a word deletes and inserts it whole: "lazy" never shares letters.
        assert_eq!(text.matches("lazy").count(), 1);
    }

    #[test]
    fn hidden_characters_sit_at_the_next_present_one() {
        let h = history(&REVISIONS);
        let cols = h.columns(0);
        let text: String = h.chars.iter().collect();
        // In "the fox", every hidden character before "fox" sits at the column of 'f'.
        let quick = text.find("quick").unwrap();
        assert_eq!(cols[quick], 4);
        // Characters after the last present one sit at the end of the line.
        let dog = text.find("dog").unwrap();
        assert_eq!(cols[dog], 7);
    }
}
