//! The animated document written as it is made: the static document is marked once
//! ([`splice::mark`]), then walked from start to end a run of animated elements at a
//! time. Each run's unit groups and path animations are made on the thread pool, spliced
//! into the run's stretch of the static text and written, then freed, so the animation of
//! a large scene is never held whole (it was most of a large export's memory).
//!
//! The splice is the one a single list of edits sorted by position would make: edits that
//! fall past the stretch being written (a unit's closing tags) wait for theirs, and edits
//! at one offset keep the order in which the whole-document writer made them (units by
//! index, then paths in document order, then markers, the definitions and the size).

use std::collections::BinaryHeap;
use std::io::{self, Write};
use std::ops::Range;

use foldhash::HashSet;

use super::splice::{self, Element, attr as tag_attr};
use super::{Defs, Part, SmilReport, UnitGroups, Writer, changes, par_map, uses_paint_server};
use crate::frame::output_size_edit;
use gmotion::Warning;

/// Animated elements made and written at a time: enough to keep every thread busy, few
/// enough that a run's text is a few megabytes.
const RUN: usize = 1024;

/// Who made an edit, in the order the whole-document writer made them: edits at one
/// offset apply in this order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Maker {
    /// A unit's groups: (unit index, 0 for the opening, 1 for the closing).
    Unit(usize, u8),
    /// A path's animation: (its index in document order, the edit's index in its part).
    Path(usize, usize),
    /// A marker id removed.
    Marker,
    /// The tinted definitions.
    Defs,
    /// The output size.
    Size,
}

/// One edit of the static text: `range` replaced by `text`.
#[derive(Debug, PartialEq, Eq)]
struct Edit {
    range: Range<usize>,
    maker: Maker,
    text: String,
}

impl Edit {
    /// Where it sorts: by position, insertions before replacements, then by maker.
    fn key(&self) -> (usize, bool, Maker) {
        (
            self.range.start,
            self.range.end != self.range.start,
            self.maker,
        )
    }
}

impl Ord for Edit {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        // Reversed: `BinaryHeap` pops its greatest, the edits must come first to last.
        other.key().cmp(&self.key())
    }
}

impl PartialOrd for Edit {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

/// An element the animation touches, by where its start tag is.
#[derive(Clone, Copy)]
enum Anchor {
    /// A unit's node (index into the animated units).
    Unit(usize),
    /// A path inside units (index into the marked paths).
    Path(usize),
}

impl Writer<'_> {
    /// Writes the whole document to `out`.
    pub(super) fn document(&self, out: &mut dyn Write) -> io::Result<SmilReport> {
        let anim = self.anim;
        let dur = self.clock.dur;
        let mut units: Vec<usize> = (0..anim.tracks.len())
            .filter(|&u| changes(&anim.tracks[u], dur))
            .collect();
        let mut lost = Part::default();
        units.retain(|&u| {
            let found = anim.scene.unit_node(u).is_some();
            if !found {
                lost.warn(u, "its node is not in the scene tree; not animated".into());
            }
            found
        });
        let marked = splice::mark(&anim.scene, &units.iter().copied().collect());
        let svg = marked.svg.as_str();
        let found = {
            let ids: Vec<&str> = marked.elements.iter().map(|(id, _)| id.as_str()).collect();
            splice::locate(svg, &ids)
        };
        // The definitions the paths' paints refer to, by id: the head's elements.
        let els = splice::elements_by_id(&svg[..svg.find("</defs>").unwrap_or(0)]);
        let mut report = Report::default();
        report.take(lost, None);

        // Where each animated element is; a unit whose node was not written is not
        // animated (and its groups are not made).
        let mut unit_element: Vec<Option<usize>> = vec![None; anim.tracks.len()];
        for &(u, e) in &marked.units {
            unit_element[u] = Some(e);
        }
        let mut anchors: Vec<(usize, Anchor)> = Vec::with_capacity(units.len());
        let mut unit_els: Vec<Option<Element>> = Vec::with_capacity(units.len());
        for (i, &u) in units.iter().enumerate() {
            let el = unit_element[u].and_then(|e| found[e]);
            match el {
                Some(el) => anchors.push((el.tag.start, Anchor::Unit(i))),
                None => {
                    let mut part = Part::default();
                    part.warn(u, "its node was not written; not animated".into());
                    report.take(part, Some(Maker::Unit(u, 0)));
                }
            }
            unit_els.push(el);
        }
        drop(unit_element);

        let mut pending: BinaryHeap<Edit> = BinaryHeap::new();
        // A tinted gradient or pattern is copied under a fresh id, and ids are handed out
        // in document order: paths painted with one are written first, in order, and their
        // definitions go into the head. The copies' ids avoid the markers too.
        let servers = marked.paths.iter().any(|mp| uses_paint_server(mp.path));
        let markers: HashSet<&str> = marked
            .elements
            .iter()
            .filter(|(_, marker)| servers && *marker)
            .map(|(id, _)| id.as_str())
            .collect();
        let mut defs = Defs {
            text: String::new(),
            node_ids: &marked.node_ids,
            markers: &markers,
            els: &els,
            given: HashSet::default(),
        };
        for (i, mp) in marked.paths.iter().enumerate() {
            let Some(el) = found[mp.element] else {
                continue;
            };
            if uses_paint_server(mp.path) {
                let mut part = Part::default();
                self.path(mp, &el, svg, &els, &mut part, Some(&mut defs));
                report.take_edits(part, i, &mut pending);
            } else {
                anchors.push((el.tag.start, Anchor::Path(i)));
            }
        }
        anchors.sort_by_key(|a| a.0);
        if !defs.text.is_empty() {
            let text = std::mem::take(&mut defs.text);
            let (at, text) = match svg.find("</defs>") {
                Some(at) => (at, text),
                None => {
                    let at = svg.find(">\n").map_or(0, |i| i + 2);
                    (at, format!("<defs>\n{text}</defs>\n"))
                }
            };
            pending.push(Edit {
                range: at..at,
                maker: Maker::Defs,
                text,
            });
        }
        if let Some(fit) = self.opts.size.fit(anim.scene.width, anim.scene.height)
            && !fit.is_canvas()
            && let Some((range, text)) = output_size_edit(svg, &fit)
        {
            pending.push(Edit {
                range,
                maker: Maker::Size,
                text,
            });
        }
        // The range of each marker's ` id="…"`, quotes included, in document order.
        let marker_range = |(&(_, marker), el): (&(String, bool), &Option<Element>)| {
            let el = el.filter(|_| marker)?;
            let (r, _) = tag_attr(&svg[el.tag.start..el.tag.end], "id")?;
            Some(el.tag.start + r.start - 5..el.tag.start + r.end + 1)
        };
        let mut markers: Vec<Range<usize>> = marked
            .elements
            .iter()
            .zip(&found)
            .filter_map(marker_range)
            .collect();
        markers.sort_by_key(|r| r.start);
        let mut markers = markers.into_iter().peekable();

        let mut at = 0;
        let mut text = String::new();
        for (k, run) in anchors.chunks(RUN).enumerate() {
            // What this run writes ends where the next run's first element starts.
            let end = anchors.get((k + 1) * RUN).map_or(usize::MAX, |a| a.0);
            let parts = par_map(run, |&(_, anchor)| match anchor {
                Anchor::Unit(i) => {
                    let u = units[i];
                    let mut part = Part::default();
                    let groups = self.unit(u, &mut part);
                    if let (Some(UnitGroups { open, depth }), Some(el)) = (groups, unit_els[i]) {
                        part.insert(el.tag.start, open);
                        part.insert(el.end, "\n</g>".repeat(depth));
                    }
                    (part, Maker::Unit(u, 0))
                }
                Anchor::Path(i) => {
                    let mp = &marked.paths[i];
                    let mut part = Part::default();
                    if let Some(el) = &found[mp.element] {
                        self.path(mp, el, svg, &els, &mut part, None);
                    }
                    (part, Maker::Path(i, 0))
                }
            });
            for (part, maker) in parts {
                report.take(part_edits(part, maker, &mut pending), Some(maker));
            }
            while let Some(r) = markers.next_if(|r| r.start < end) {
                pending.push(Edit {
                    range: r,
                    maker: Maker::Marker,
                    text: String::new(),
                });
            }
            text.clear();
            while let Some(e) = pending.peek()
                && e.range.start < end
            {
                let e = pending.pop().expect("peeked");
                text.push_str(&svg[at..e.range.start.max(at)]);
                text.push_str(&e.text);
                at = at.max(e.range.end);
            }
            let stop = end.min(svg.len()).max(at);
            text.push_str(&svg[at..stop]);
            at = stop;
            out.write_all(text.as_bytes())?;
        }
        // No animated element: the edits of the head, then the rest.
        text.clear();
        while let Some(e) = pending.pop() {
            text.push_str(&svg[at..e.range.start.max(at)]);
            text.push_str(&e.text);
            at = at.max(e.range.end);
        }
        text.push_str(&svg[at..]);
        out.write_all(text.as_bytes())?;
        Ok(report.finish(anim))
    }
}

/// Moves `part`'s edits, made by `maker` (its first edit's), into `pending`; returns the
/// rest of the part.
fn part_edits(mut part: Part, maker: Maker, pending: &mut BinaryHeap<Edit>) -> Part {
    for (n, (range, text)) in part.edits.drain(..).enumerate() {
        let maker = match maker {
            // A unit's part holds its opening, then its closing.
            Maker::Unit(u, _) => Maker::Unit(u, n.min(1) as u8),
            Maker::Path(i, _) => Maker::Path(i, n),
            other => other,
        };
        pending.push(Edit { range, maker, text });
    }
    part
}

/// Warnings and counts gathered from the parts, put in the order the whole-document
/// writer gave them at the end.
#[derive(Default)]
struct Report {
    /// (who, unit, message), `None` first (units that are not in the scene tree).
    warnings: Vec<(Option<Maker>, usize, String)>,
    exact: usize,
    baked: usize,
}

impl Report {
    fn take(&mut self, part: Part, by: Option<Maker>) {
        self.exact += part.exact;
        self.baked += part.baked;
        // A part's own warnings keep their order: only the maker's index sorts them.
        let by = by.map(|m| match m {
            Maker::Unit(u, _) => Maker::Unit(u, 0),
            Maker::Path(i, _) => Maker::Path(i, 0),
            other => other,
        });
        self.warnings
            .extend(part.warnings.into_iter().map(|(u, m)| (by, u, m)));
    }

    /// [`Self::take`] for path `i`'s part, its edits into `pending`.
    fn take_edits(&mut self, part: Part, i: usize, pending: &mut BinaryHeap<Edit>) {
        let maker = Maker::Path(i, 0);
        let rest = part_edits(part, maker, pending);
        self.take(rest, Some(maker));
    }

    fn finish(mut self, anim: &gmotion::motion::Animation) -> SmilReport {
        // Stable: a part's warnings stay in their order.
        self.warnings.sort_by_key(|w| w.0);
        let warnings = self
            .warnings
            .into_iter()
            .map(|(_, unit, message)| {
                let s = &anim.scene.shapes[unit];
                Warning::about(format!("{}:{}", s.tag, s.id), message)
            })
            .collect();
        SmilReport {
            warnings,
            exact_segments: self.exact,
            baked_segments: self.baked,
        }
    }
}
