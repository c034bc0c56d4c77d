//! A Lottie source played as animated SVG (`gmotion convert anim.json -o anim.svg`, and
//! `gmotion animate anim.json motion.gm -o out.svg` when the source moves by itself): every
//! frame drawn by gmotion's own renderer (the source evaluated at the frame, moved by the
//! animation's tracks), each frame that differs from the one before a `<g>` of its own,
//! shown in turn by a discrete SMIL `display` animation. Frame for frame what a GIF shows,
//! but in vectors, scalable and without a palette. A viewer without SMIL shows the first
//! frame.
//!
//! Frames share what they draw alike: an element (with everything inside it) that stands
//! the same in two frames is written once, in the document's `<defs>`, and each frame
//! shows it through a `<use>`; so is a run of such sibling elements (as `<use>`s of each). A scene where a few parts move over a still backdrop costs
//! the backdrop once and the moving parts once a frame. Elements that refer to a frame's
//! gradients, clip paths, masks or filters stay in their frame, whose `<defs>` entries are
//! named after it (`f12_0`, `f12_1`, …, see [`frame::frame_with_ids`]); their content is
//! shared where it can be, and so is what a mask or a pattern holds (a clip path may
//! `<use>` a shape only, not a group). The file is bounded by [`MAX_BYTES`] of frames.
//!
//! Why frames rather than animated elements: a Lottie's own motion (path keyframes, trims,
//! mattes, repeaters, time remapping) has no general counterpart in SMIL's attribute
//! animation; frames are exact wherever gmotion's own render is.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::hash::{DefaultHasher, Hash, Hasher};
use std::path::Path;

use gmotion_export_svg::frame;
use rayon::prelude::*;

use crate::{LottieSource, Options, OutputError, Stage};

/// The most bytes the frames of a played Lottie may take, as drawn before sharing (256
/// MiB): they are all held in memory to find what they share. Past it, a GIF, APNG or
/// frames folder says the same in far less.
pub const MAX_BYTES: usize = 256 << 20;

/// Elements shorter than this are written in their frame: a `<use>` of them would save
/// little or nothing.
const MIN_SHARED: usize = 64;

/// Frames drawn at a time, in parallel: enough to keep the cores busy, few enough that a
/// file past [`MAX_BYTES`] is refused before much more than that is drawn.
const BATCH: usize = 64;

/// Whether `src` moves by itself: its first frame and some later one differ.
pub(crate) fn moves(src: &LottieSource) -> bool {
    let frames = ((src.duration() * src.fps()).round() as usize).max(1);
    let at = |k: usize| {
        src.scene_at(src.frame_at(k as f64 / src.fps()))
            .map(|(scene, _)| frame::scene_svg(&scene))
            .ok()
    };
    let first = at(0);
    // Eight frames spread over the composition: a source that differs nowhere among them
    // but moves between them is rare, and still drawn (at its reference frame) with the
    // animation's motion.
    (1..=8).any(|i| at(i * (frames - 1) / 8) != first)
}

/// A frame that differs from the one before it.
struct Shown {
    /// The first frame it stands for.
    frame: usize,
    /// Its SVG document, its `<defs>` entries named after [`ids`].
    svg: String,
}

/// What frame `k`'s `<defs>` entries are named after. `_` appears nowhere else in a
/// frame's text (numbers, colours, path data, base64 image data), so frames can be
/// compared with their names told apart ([`same_frame`]).
fn ids(k: usize) -> String {
    format!("f{k}_")
}

/// Whether frames `a` (named after `ids(ka)`) and `b` (after `ids(kb)`) draw the same.
fn same_frame(a: &str, ka: usize, b: &str, kb: usize) -> bool {
    a.split(&ids(ka)).eq(b.split(&ids(kb)))
}

/// `stage` played from its first frame to its last as SMIL, for `path` (named in errors).
pub(crate) fn smil(stage: Stage, path: &Path, opts: &Options) -> Result<String, OutputError> {
    let anim = stage.anim;
    let frames = anim.frame_count();
    let sampler = anim.sampler();
    let mut shown: Vec<Shown> = Vec::new();
    let mut bytes = 0usize;
    for first in (0..frames).step_by(BATCH) {
        let drawn: Vec<String> = (first..(first + BATCH).min(frames))
            .into_par_iter()
            .map(|k| stage.svg(Some(&sampler), path, (k, anim.frame_time(k)), &ids(k)))
            .collect::<Result<_, _>>()?;
        for (k, svg) in (first..).zip(drawn) {
            if shown
                .last()
                .is_some_and(|last| same_frame(&last.svg, last.frame, &svg, k))
            {
                continue;
            }
            bytes += svg.len() + 256;
            if bytes > MAX_BYTES {
                return Err(OutputError::TooLargeAsSvg {
                    path: path.to_path_buf(),
                    frames: k + 1,
                    max: MAX_BYTES,
                });
            }
            shown.push(Shown { frame: k, svg });
        }
    }
    // Frames are split twice, to count and to write, rather than held split: an element
    // takes about as much memory as its text.
    let hashes: Vec<Vec<u64>> = shown
        .par_iter()
        .map(|s| Page::parse(&s.svg).shareable_hashes().collect())
        .collect();
    let seen = count(hashes.into_iter().flatten());
    let hashes: Vec<Vec<u64>> = shown
        .par_iter()
        .map(|s| Page::parse(&s.svg).run_hashes(&seen))
        .collect();
    let runs = count(hashes.into_iter().flatten());
    let mut shared = Shared::new(seen, runs);
    let (width, height) = (anim.scene.width, anim.scene.height);
    let dur = frames as f64 / anim.fps;
    let mut body = String::with_capacity(bytes / 4);
    for (i, s) in shown.iter().enumerate() {
        let page = Page::parse(&s.svg);
        let end = shown.get(i + 1).map_or(frames, |next| next.frame);
        body.push_str(if i == 0 {
            "<g>\n"
        } else {
            "<g display=\"none\">\n"
        });
        if shown.len() > 1 {
            // Shown from frame `k` up to the next distinct frame, hidden otherwise.
            let (on, off) = (s.frame as f64 / frames as f64, end as f64 / frames as f64);
            let (values, times) = match (i == 0, end == frames) {
                (true, _) => ("inline;none".to_string(), format!("0;{off}")),
                (false, true) => ("none;inline".to_string(), format!("0;{on}")),
                (false, false) => ("none;inline;none".to_string(), format!("0;{on};{off}")),
            };
            let _ = writeln!(
                body,
                "<animate attributeName=\"display\" values=\"{values}\" keyTimes=\"{times}\" dur=\"{dur}s\" calcMode=\"discrete\" repeatCount=\"indefinite\"/>"
            );
        }
        if !page.defs.text.is_empty() {
            body.push_str("<defs>\n");
            page.defs.write(&mut shared, &mut body);
            body.push_str("</defs>\n");
        }
        page.body.write(&mut shared, &mut body);
        body.push_str("</g>\n");
    }
    let mut out = String::with_capacity(body.len() + shared.defs.len() + 256);
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}">"#
    );
    if !shared.defs.is_empty() {
        out.push_str("<defs>\n");
        out.push_str(&shared.defs);
        out.push_str("</defs>\n");
    }
    out.push_str(&body);
    out.push_str("</svg>\n");
    Ok(match opts.size.fit(width, height) {
        Some(fit) if !fit.is_canvas() => frame::with_output_size(&out, &fit),
        _ => out,
    })
}

/// The elements frames share, as they are written.
struct Shared<'a> {
    /// How often each shareable element's hash stands in all frames.
    seen: HashMap<u64, u32>,
    /// How often each run of repeated siblings (see [`Lines::runs`]) stands in all frames.
    runs: HashMap<u64, u32>,
    /// The elements written to [`Self::defs`] so far: hash → (number, text).
    index: HashMap<u64, (usize, &'a str)>,
    /// `<g id="sN">…</g>` for each shared element.
    defs: String,
}

impl<'a> Shared<'a> {
    fn new(seen: HashMap<u64, u32>, runs: HashMap<u64, u32>) -> Self {
        Shared {
            seen,
            runs,
            index: HashMap::new(),
            defs: String::new(),
        }
    }

    /// Writes `text` (hashed as `hash`) as a `<use>` of its shared copy, made on first use
    /// from what `content` writes: the text itself, or for a run of elements a `<use>` of
    /// each (so an element that stands alone elsewhere is not written twice).
    fn share(
        &mut self,
        hash: u64,
        text: &'a str,
        out: &mut String,
        content: impl FnOnce(&mut Self, &mut String),
    ) {
        let id = match self.index.get(&hash) {
            // Equal hashes of different text: written in place.
            Some(&(id, shared)) => (shared == text).then_some(id),
            None => {
                let mut body = String::new();
                content(self, &mut body);
                let id = self.index.len();
                self.index.insert(hash, (id, text));
                let _ = writeln!(self.defs, "<g id=\"s{id}\">");
                self.defs.push_str(&body);
                self.defs.push_str("</g>\n");
                Some(id)
            }
        };
        match id {
            Some(id) => {
                let _ = writeln!(out, "<use href=\"#s{id}\"/>");
            }
            None => out.push_str(text),
        }
    }

    /// [`Self::share`] for an element's own text.
    fn share_text(&mut self, hash: u64, text: &'a str, out: &mut String) {
        self.share(hash, text, out, |_, body| body.push_str(text));
    }
}

/// Whether `el` may be shared and stands in more than one place (`seen` counts them).
fn repeated(seen: &HashMap<u64, u32>, el: &El) -> bool {
    el.shareable && seen.get(&el.hash).is_some_and(|&n| n > 1)
}

/// How often each value stands in `hashes`.
fn count(hashes: impl Iterator<Item = u64>) -> HashMap<u64, u32> {
    let mut seen: HashMap<u64, u32> = HashMap::new();
    for h in hashes {
        *seen.entry(h).or_default() += 1;
    }
    seen
}

/// One element of a frame's body, with everything inside it.
struct El<'a> {
    /// Where its text starts in the text split.
    start: usize,
    /// Its lines, from its start tag to its end tag.
    text: &'a str,
    /// Its start tag's line, the whole element for an empty one.
    open: &'a str,
    /// Its end tag's line; empty for an empty element.
    close: &'a str,
    /// The index past its last descendant (elements are listed in document order).
    end: usize,
    /// Identifies its text (with its descendants').
    hash: u64,
    /// Whether it may be shared: long enough, and referring to none of its frame's ids.
    shareable: bool,
}

/// A frame document split for sharing.
struct Page<'a> {
    /// Its `<defs>` entries: what a mask or a pattern holds may be shared (a clip path may
    /// `<use>` only a shape, not a group).
    defs: Lines<'a>,
    /// Its body.
    body: Lines<'a>,
}

/// Text written one element a line, split into its elements.
struct Lines<'a> {
    /// The text.
    text: &'a str,
    /// Its elements in document order; empty when the text is not one element a line as
    /// [`frame`] writes it (then it is written as it stands).
    els: Vec<El<'a>>,
}

impl<'a> Page<'a> {
    /// `svg`, a document [`frame`] wrote: its root start tag, `<defs>` (if any), the body
    /// one element a line, `</svg>`.
    fn parse(svg: &'a str) -> Page<'a> {
        let after_root = svg.find(">\n").map_or(svg.len(), |i| i + 2);
        let mut rest = &svg[after_root..];
        let mut defs = "";
        if let Some(d) = rest.strip_prefix("<defs>\n")
            && let Some(close) = d.find("</defs>\n")
        {
            defs = &d[..close];
            rest = &d[close + "</defs>\n".len()..];
        }
        let body = rest.strip_suffix("</svg>\n").unwrap_or(rest);
        let mut defs = Lines::split(defs);
        // Only the content of masks and patterns is shared: the entries themselves carry
        // the frame's names, and a clip path's content must stay shapes.
        let mut i = 0;
        let mut shared_inside = vec![false; defs.els.len()];
        while i < defs.els.len() {
            let entry = &defs.els[i];
            if entry.open.starts_with("<mask ") || entry.open.starts_with("<pattern ") {
                shared_inside[i + 1..entry.end].fill(true);
            }
            i = entry.end;
        }
        for (el, inside) in defs.els.iter_mut().zip(shared_inside) {
            el.shareable &= inside;
        }
        Page {
            defs,
            body: Lines::split(body),
        }
    }

    /// The hashes of its runs of repeated siblings.
    fn run_hashes(&self, seen: &HashMap<u64, u32>) -> Vec<u64> {
        let mut hashes = Vec::new();
        for lines in [&self.defs, &self.body] {
            let parents = std::iter::once((0, lines.els.len()))
                .chain((0..lines.els.len()).map(|i| (i + 1, lines.els[i].end)));
            for (from, to) in parents {
                hashes.extend(lines.runs(from, to, seen).into_iter().map(|r| r.hash));
            }
        }
        hashes
    }

    /// The hashes of the elements that may be shared.
    fn shareable_hashes(&self) -> impl Iterator<Item = u64> + '_ {
        (self.defs.els.iter())
            .chain(&self.body.els)
            .filter(|e| e.shareable)
            .map(|e| e.hash)
    }
}

impl<'a> Lines<'a> {
    fn split(text: &'a str) -> Lines<'a> {
        Lines {
            text,
            els: elements(text).unwrap_or_default(),
        }
    }

    /// Appends the text, each element or run of sibling elements that stands in more than
    /// one place as a `<use>` of its shared copy.
    fn write(&self, shared: &mut Shared<'a>, out: &mut String) {
        if self.els.is_empty() {
            out.push_str(self.text);
            return;
        }
        self.write_children(0, self.els.len(), shared, out);
    }

    /// Writes the elements from `from` up to `to`, siblings.
    fn write_children(&self, from: usize, to: usize, shared: &mut Shared<'a>, out: &mut String) {
        let runs = self.runs(from, to, &shared.seen);
        let mut runs = runs.iter().peekable();
        let mut i = from;
        while i < to {
            // A run found here but standing nowhere else is written element by element.
            if let Some(run) = runs.next_if(|r| r.first == i)
                && shared.runs.get(&run.hash).is_some_and(|&n| n > 1)
            {
                let text = &self.text[run.text.clone()];
                shared.share(run.hash, text, out, |shared, body| {
                    let mut j = run.first;
                    while j < run.end {
                        let el = &self.els[j];
                        shared.share_text(el.hash, el.text, body);
                        j = el.end;
                    }
                });
                i = run.end;
                continue;
            }
            i = self.write_el(i, shared, out);
        }
    }

    /// Writes element `i`; returns the index past it.
    fn write_el(&self, i: usize, shared: &mut Shared<'a>, out: &mut String) -> usize {
        let el = &self.els[i];
        if repeated(&shared.seen, el) {
            shared.share_text(el.hash, el.text, out);
            return el.end;
        }
        out.push_str(el.open);
        self.write_children(i + 1, el.end, shared, out);
        out.push_str(el.close);
        el.end
    }

    /// The runs of two or more consecutive repeated elements among the siblings from
    /// `from` up to `to`: a backdrop of many still shapes under one moving group is one
    /// `<use>` a frame rather than one a shape.
    fn runs(&self, from: usize, to: usize, seen: &HashMap<u64, u32>) -> Vec<Run> {
        let mut runs = Vec::new();
        let mut i = from;
        while i < to {
            if !repeated(seen, &self.els[i]) {
                i = self.els[i].end;
                continue;
            }
            let (first, mut last) = (i, i);
            let mut h = DefaultHasher::new();
            while i < to && repeated(seen, &self.els[i]) {
                self.els[i].hash.hash(&mut h);
                last = i;
                i = self.els[i].end;
            }
            if last > first {
                let stop = self.els[last].start + self.els[last].text.len();
                runs.push(Run {
                    first,
                    end: i,
                    hash: h.finish(),
                    text: self.els[first].start..stop,
                });
            }
        }
        runs
    }
}

/// Consecutive sibling elements, each repeated.
struct Run {
    /// Its first element.
    first: usize,
    /// The index past its last element's descendants.
    end: usize,
    /// Identifies the elements' hashes in order.
    hash: u64,
    /// Where its text lies in the text split.
    text: std::ops::Range<usize>,
}

/// The elements of `body`, one a line as [`frame`] writes them: a start tag, an empty
/// element, or an end tag on each line. `None` if the text is not so.
fn elements(body: &str) -> Option<Vec<El<'_>>> {
    let mut els: Vec<El> = Vec::new();
    // Elements whose end tag is still to come.
    let mut open: Vec<usize> = Vec::new();
    let mut at = 0;
    for line in body.split_inclusive('\n') {
        let (start, end) = (at, at + line.len());
        at = end;
        let tag = line.strip_suffix('\n')?;
        if tag.starts_with("</") {
            let i = open.pop()?;
            els[i].text = &body[els[i].start..end];
            els[i].close = line;
            continue;
        }
        if !tag.starts_with('<') || !tag.ends_with('>') {
            return None;
        }
        els.push(El {
            start,
            text: line,
            open: line,
            close: "",
            end: 0,
            hash: 0,
            shareable: false,
        });
        let name_end = tag[1..].find([' ', '>', '/']).map_or(tag.len(), |n| n + 1);
        // An empty element, or one with its text content on its line (`<a>…</a>`), is
        // complete.
        if !tag.ends_with("/>") && !tag.ends_with(&format!("</{}>", &tag[1..name_end])) {
            open.push(els.len() - 1);
        }
    }
    if !open.is_empty() {
        return None;
    }
    // Ends, hashes and what may be shared, innermost first.
    let n = els.len();
    let mut refers = vec![false; n];
    for i in (0..n).rev() {
        let mut h = DefaultHasher::new();
        els[i].open.hash(&mut h);
        refers[i] = refers_to_ids(els[i].open);
        let stop = els[i].start + els[i].text.len();
        let mut child = i + 1;
        while child < n && els[child].start < stop {
            els[child].hash.hash(&mut h);
            refers[i] |= refers[child];
            child = els[child].end;
        }
        els[i].close.hash(&mut h);
        let el = &mut els[i];
        el.end = child;
        el.hash = h.finish();
        el.shareable = !refers[i] && el.text.len() >= MIN_SHARED;
    }
    Some(els)
}

/// Whether a start tag refers to an id (`url(#…)`, `href="#…"`): a frame's ids are its own.
fn refers_to_ids(tag: &str) -> bool {
    tag.contains("url(#") || tag.contains("href=\"#")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A frame body: a moving group referring to the frame's clip, a still group inside
    /// it, and a still path at the top.
    const BODY: &str = "<g clip-path=\"url(#f0_0)\">\n<g transform=\"translate(1 2)\">\n<path d=\"M0 0 L10 0 L10 10 L0 10 Z M2 2 L8 2 L8 8 L2 8 Z\" fill=\"#ff0000\"/>\n</g>\n</g>\n<path d=\"M0 0 L20 0 L20 20 L0 20 Z M5 5 L6 6\" fill=\"#00ff00\" stroke=\"#000000\"/>\n";

    /// What `pages` share, counted as [`smil`] counts it.
    fn counted<'a>(pages: &[Page<'a>]) -> Shared<'a> {
        let seen = count(pages.iter().flat_map(Page::shareable_hashes));
        let runs = count(pages.iter().flat_map(|p| p.run_hashes(&seen)));
        Shared::new(seen, runs)
    }

    #[test]
    fn elements_nest_and_refer_as_written() {
        let els = elements(BODY).expect("one element a line");
        assert_eq!(els.len(), 4);
        // Document order, each with the index past its descendants.
        assert_eq!(els.iter().map(|e| e.end).collect::<Vec<_>>(), [3, 3, 3, 4]);
        assert_eq!(
            els[0].text,
            &BODY[..BODY.find("<path d=\"M0 0 L20").unwrap()]
        );
        assert!(els[1].text.starts_with("<g transform") && els[1].text.ends_with("</g>\n"));
        // The clipped group refers to its frame's ids: it stays in its frame, while what
        // it holds may be shared.
        assert_eq!(
            els.iter().map(|e| e.shareable).collect::<Vec<_>>(),
            [false, true, true, true]
        );
        // The same text hashes alike; a different one not.
        let again = elements(BODY).unwrap();
        assert!(els.iter().zip(&again).all(|(a, b)| a.hash == b.hash));
        assert_ne!(els[1].hash, els[2].hash);
    }

    #[test]
    fn text_that_is_not_one_element_a_line_is_kept_whole() {
        for body in [
            "<g>\n<path/>\n",
            "</g>\n",
            "<g>\ntext\n</g>\n",
            "<g><path/>",
        ] {
            assert!(elements(body).is_none(), "{body:?}");
        }
        assert_eq!(elements("<text x=\"1\">a b</text>\n").unwrap()[0].end, 1);
    }

    #[test]
    fn frames_are_compared_with_their_names_told_apart() {
        let a = "<defs>\n<clipPath id=\"f3_0\"/>\n</defs>\n<g clip-path=\"url(#f3_0)\">\n";
        let b = a.replace("f3_", "f17_");
        assert!(same_frame(a, 3, &b, 17));
        assert!(!same_frame(a, 3, &b.replace("clip-path", "mask"), 17));
        assert!(!same_frame(a, 3, a, 17));
    }

    #[test]
    fn frames_share_what_they_draw_alike() {
        let moved = BODY.replace("translate(1 2)", "translate(3 4)");
        let docs = [BODY.to_string(), moved].map(|body| {
            format!("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"9\" height=\"9\">\n<defs>\n<clipPath id=\"f0_0\"/>\n</defs>\n{body}</svg>\n")
        });
        let pages: Vec<Page> = docs.iter().map(|d| Page::parse(d)).collect();
        let mut shared = counted(&pages);
        let written: Vec<String> = pages
            .iter()
            .map(|p| {
                assert_eq!(p.defs.text, "<clipPath id=\"f0_0\"/>\n");
                let mut out = String::new();
                p.body.write(&mut shared, &mut out);
                out
            })
            .collect();
        // The red square and the still path stand in both frames: written once each.
        assert_eq!(shared.index.len(), 2);
        assert_eq!(shared.defs.matches("<g id=\"s").count(), 2);
        for (w, doc) in written.iter().zip(&docs) {
            assert_eq!(w.matches("<use href=\"#s").count(), 2);
            // Put back, each frame is what was drawn.
            let mut back = w.clone();
            for (id, text) in shared.index.values() {
                back = back.replace(&format!("<use href=\"#s{id}\"/>\n"), text);
            }
            assert!(doc.contains(&back), "{back}");
        }
    }

    #[test]
    fn runs_of_repeated_siblings_are_shared_as_one() {
        let still: String = (0..3)
            .map(|k| format!("<path d=\"M{k} 0 L20 0 L20 20 L0 20 Z M5 5 L6 6 L7 7 L8 8\" fill=\"#ffffff\"/>\n"))
            .collect();
        let docs: Vec<String> = (0..3)
            .map(|k| format!("<svg>\n<g transform=\"translate({k} 0)\">\n</g>\n{still}</svg>\n"))
            .collect();
        let pages: Vec<Page> = docs.iter().map(|d| Page::parse(d)).collect();
        let mut shared = counted(&pages);
        for (k, p) in pages.iter().enumerate() {
            let mut out = String::new();
            p.body.write(&mut shared, &mut out);
            assert_eq!(
                out,
                format!("<g transform=\"translate({k} 0)\">\n</g>\n<use href=\"#s3\"/>\n")
            );
        }
        // Each shape once, and the run as `<use>`s of them.
        let mut defs = String::new();
        for (k, line) in still.lines().enumerate() {
            defs.push_str(&format!("<g id=\"s{k}\">\n{line}\n</g>\n"));
        }
        defs.push_str(
            "<g id=\"s3\">\n<use href=\"#s0\"/>\n<use href=\"#s1\"/>\n<use href=\"#s2\"/>\n</g>\n",
        );
        assert_eq!(shared.defs, defs);
    }

    #[test]
    fn what_masks_hold_is_shared_and_what_clip_paths_hold_is_not() {
        let path = "<path d=\"M0 0 L20 0 L20 20 L0 20 Z M5 5 L6 6 L7 7 L8 8\" fill=\"#ffffff\"/>\n";
        let defs = |k: usize| {
            format!(
                "<clipPath id=\"f{k}_0\">\n{path}</clipPath>\n<mask id=\"f{k}_1\">\n{path}</mask>\n"
            )
        };
        let docs: Vec<String> = (0..2)
            .map(|k| {
                format!(
                    "<svg>\n<defs>\n{}</defs>\n<g mask=\"url(#f{k}_1)\">\n</g>\n</svg>\n",
                    defs(k)
                )
            })
            .collect();
        let pages: Vec<Page> = docs.iter().map(|d| Page::parse(d)).collect();
        let mut shared = counted(&pages);
        for (k, p) in pages.iter().enumerate() {
            let mut out = String::new();
            p.defs.write(&mut shared, &mut out);
            assert_eq!(
                out,
                format!(
                    "<clipPath id=\"f{k}_0\">\n{path}</clipPath>\n<mask id=\"f{k}_1\">\n<use href=\"#s0\"/>\n</mask>\n"
                )
            );
        }
        assert_eq!(shared.defs, format!("<g id=\"s0\">\n{path}</g>\n"));
    }

    /// The frames of `svg` (a played document), each as the text between its wrapper's
    /// start tag (and `display` animation) and its end tag, every `<use>` of a shared
    /// element put back.
    #[cfg(feature = "players")]
    fn frames_put_back(svg: &str) -> Vec<String> {
        let rest = svg.split_once(">\n").unwrap().1;
        let (defs, body) = match rest.strip_prefix("<defs>\n") {
            Some(r) => r.split_once("</defs>\n").unwrap(),
            None => ("", rest),
        };
        let mut shared = HashMap::new();
        let lines = Lines::split(defs);
        let mut i = 0;
        while i < lines.els.len() {
            let el = &lines.els[i];
            let id = &el.open["<g id=\"".len()..el.open.len() - "\">\n".len()];
            let inner = &el.text[el.open.len()..el.text.len() - el.close.len()];
            shared.insert(format!("<use href=\"#{id}\"/>\n"), inner);
            i = el.end;
        }
        // A shared run is `<use>`s of shared elements.
        fn put_back(line: &str, shared: &HashMap<String, &str>, out: &mut String) {
            match shared.get(line) {
                Some(inner) => inner
                    .split_inclusive('\n')
                    .for_each(|l| put_back(l, shared, out)),
                None => out.push_str(line),
            }
        }
        let body = body.strip_suffix("</svg>\n").unwrap();
        let mut frames: Vec<String> = Vec::new();
        for line in body.split_inclusive('\n') {
            if line == "<g>\n" || line == "<g display=\"none\">\n" {
                frames.push(String::new());
            } else if !line.starts_with("<animate attributeName=\"display\"") {
                put_back(line, &shared, frames.last_mut().unwrap());
            }
        }
        for frame in &mut frames {
            assert!(frame.ends_with("</g>\n"));
            frame.truncate(frame.len() - "</g>\n".len());
        }
        frames
    }

    /// Every frame of real files (an embedded image under moving parts, masks whose
    /// content stands still), its `<use>`s put back, is the document drawn for it; and
    /// sharing made the file several times smaller. Reads the Lottie corpus that
    /// `tests/conformance/install.sh` fetches, so only with the `players` feature.
    #[cfg(feature = "players")]
    #[test]
    fn each_frame_put_back_is_the_frame_drawn() {
        let corpus =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/conformance/lottie-corpus");
        for name in [
            "rlottie-python__image_embedded",
            "rlottie-python__1643-exploding-star",
        ] {
            let file = corpus.join(format!("{name}.json"));
            let imported = gmotion_import_lottie::load(&file, &Default::default()).unwrap();
            let src = &imported.source;
            let anim = gmotion::motion::Animation {
                scene: imported.scene.clone(),
                duration: src.duration(),
                fps: src.fps(),
                looping: true,
                tracks: vec![Default::default(); imported.scene.shapes.len()],
            };
            let stage = Stage {
                anim: &anim,
                source: Some(src),
            };
            let played = smil(stage, &file, &Options::default()).unwrap();
            let frames = frames_put_back(&played);
            let sampler = anim.sampler();
            let mut drawn: Vec<String> = Vec::new();
            let mut last: Option<(String, usize)> = None;
            for k in 0..anim.frame_count() {
                let svg = stage
                    .svg(Some(&sampler), &file, (k, anim.frame_time(k)), &ids(k))
                    .unwrap();
                if last
                    .as_ref()
                    .is_some_and(|(l, kl)| same_frame(l, *kl, &svg, k))
                {
                    continue;
                }
                let inner = svg.split_once(">\n").unwrap().1;
                drawn.push(inner.strip_suffix("</svg>\n").unwrap().to_string());
                last = Some((svg, k));
            }
            assert_eq!(frames.len(), drawn.len(), "{name}");
            assert!(frames.len() > 10, "{name}: {} frames", frames.len());
            for (k, (ours, theirs)) in frames.iter().zip(&drawn).enumerate() {
                assert!(ours == theirs, "{name}: frame {k} differs");
            }
            let whole: usize = drawn.iter().map(String::len).sum();
            assert!(
                played.len() * 3 < whole,
                "{name}: {} of {whole} bytes",
                played.len()
            );
        }
    }
}
