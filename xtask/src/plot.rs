//! Plots of input and output signals — position and velocity over time — for the
//! transition techniques of the signals-and-systems paper, as PNG files: SVG text drawn
//! here, rendered with resvg.
//!
//! [`transition_plots`] writes the pictures of `docs/img/`:
//! - `transitions_interrupted.png`: simple, spline, FIR and spring transitions on the
//!   same interrupted step input (sec. 2, 3, 5, 6): only simple transitions jump in
//!   velocity;
//! - `transitions_stall.png`: Claim 1 — retargeted ever more often, simple transitions
//!   stall while FIR transitions keep up;
//! - `spring_discretizations.png`: the spring's step response and its four
//!   discretisations at a coarse frame rate;
//! - `easings.png`: B-spline windows and pole cascades (sec. 9) with their velocities.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use gmotion::signals::{
    Discretization, Ease, Easing, FirTransition, Lti, SignalError, SimpleTransition, SmoothSpec,
    SplineTransition, Spring, System, Transition, smooth_samples,
};

/// Why a plot could not be written.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// Writing the file failed.
    #[error("{path}: {message}")]
    Io {
        /// The file.
        path: String,
        /// What happened.
        message: String,
    },
    /// The SVG did not render.
    #[error("cannot render a plot: {0}")]
    Render(String),
    /// A system could not be built.
    #[error(transparent)]
    Signal(#[from] SignalError),
}

/// Points `(x, y)` of a curve.
type Curve = Vec<(f64, f64)>;

/// A function that draws one figure into a file.
type Figure = fn(&Path) -> Result<(), PlotError>;

/// One curve: points and how to draw them.
struct Series {
    label: String,
    color: &'static str,
    dashed: bool,
    points: Vec<(f64, f64)>,
}

impl Series {
    fn new(label: impl Into<String>, color: &'static str, points: Vec<(f64, f64)>) -> Series {
        Series {
            label: label.into(),
            color,
            dashed: false,
            points,
        }
    }

    fn dashed(mut self) -> Series {
        self.dashed = true;
        self
    }
}

/// A panel: a title, axis labels and curves, drawn into a box of the figure.
struct Panel {
    title: String,
    x_label: &'static str,
    y_label: &'static str,
    series: Vec<Series>,
    /// Draw markers instead of lines (for discrete samples).
    markers: Vec<bool>,
}

impl Panel {
    fn new(title: impl Into<String>, x_label: &'static str, y_label: &'static str) -> Panel {
        Panel {
            title: title.into(),
            x_label,
            y_label,
            series: Vec::new(),
            markers: Vec::new(),
        }
    }

    fn line(mut self, s: Series) -> Panel {
        self.series.push(s);
        self.markers.push(false);
        self
    }

    fn dots(mut self, s: Series) -> Panel {
        self.series.push(s);
        self.markers.push(true);
        self
    }
}

const PANEL_W: f64 = 520.0;
const PANEL_H: f64 = 200.0;
const PAD_L: f64 = 58.0;
/// Right padding: room for the legend column when the panel has labelled curves.
const PAD_R: f64 = 14.0;
const LEGEND_W: f64 = 150.0;
const PAD_T: f64 = 30.0;
const PAD_B: f64 = 38.0;

/// "Nice" tick spacing for a range (1, 2 or 5 times a power of ten).
fn tick_step(span: f64) -> f64 {
    let raw = span / 5.0;
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * p)
}

fn fmt_tick(v: f64, step: f64) -> String {
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    // Ticks are multiples of the step; round-off near zero must not print "-0.0".
    let v = if v.abs() < 1e-9 * step { 0.0 } else { v };
    format!("{v:.decimals$}")
}

/// The ticks of an axis over `[lo, hi]`, each with its label.
fn ticks(lo: f64, hi: f64) -> Vec<(f64, String)> {
    let step = tick_step(hi - lo);
    let mut out = Vec::new();
    let mut v = (lo / step).ceil() * step;
    while v <= hi + 1e-9 {
        out.push((v, fmt_tick(v, step)));
        v += step;
    }
    out
}

/// Draws `panel` at `(x0, y0)` into `svg`.
fn draw_panel(svg: &mut String, panel: &Panel, x0: f64, y0: f64) {
    let pts = panel.series.iter().flat_map(|s| s.points.iter());
    let (mut xmin, mut xmax, mut ymin, mut ymax) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for &(x, y) in pts {
        if x.is_finite() && y.is_finite() {
            xmin = xmin.min(x);
            xmax = xmax.max(x);
            ymin = ymin.min(y);
            ymax = ymax.max(y);
        }
    }
    // An empty or flat panel still gets a unit range.
    if !xmin.is_finite() {
        (xmin, xmax) = (0.0, 1.0);
    }
    if !ymin.is_finite() {
        (ymin, ymax) = (0.0, 1.0);
    }
    if xmax <= xmin {
        xmax = xmin + 1.0;
    }
    if ymax <= ymin {
        ymax = ymin + 1.0;
    }
    let margin = 0.06 * (ymax - ymin);
    let (ymin, ymax) = (ymin - margin, ymax + margin);
    let labelled: Vec<&Series> = panel
        .series
        .iter()
        .filter(|s| !s.label.is_empty())
        .collect();
    let pad_r = if labelled.is_empty() { PAD_R } else { LEGEND_W };
    let (w, h) = (PANEL_W - PAD_L - pad_r, PANEL_H - PAD_T - PAD_B);
    let (left, top) = (x0 + PAD_L, y0 + PAD_T);
    let sx = |x: f64| left + (x - xmin) / (xmax - xmin) * w;
    let sy = |y: f64| top + (ymax - y) / (ymax - ymin) * h;
    let _ = writeln!(
        svg,
        r##"<rect x="{left}" y="{top}" width="{w}" height="{h}" fill="#fbfbfb" stroke="#999999" stroke-width="1"/>"##
    );
    // Grid and ticks.
    for (v, label) in ticks(xmin, xmax) {
        let x = sx(v);
        let _ = writeln!(
            svg,
            r##"<path d="M{x:.1} {top} V{:.1}" stroke="#e4e4e4"/><text x="{x:.1}" y="{:.1}" font-size="11" text-anchor="middle" fill="#444444">{label}</text>"##,
            top + h,
            top + h + 14.0,
        );
    }
    for (v, label) in ticks(ymin, ymax) {
        let y = sy(v);
        let _ = writeln!(
            svg,
            r##"<path d="M{left} {y:.1} H{:.1}" stroke="#e4e4e4"/><text x="{:.1}" y="{:.1}" font-size="11" text-anchor="end" fill="#444444">{label}</text>"##,
            left + w,
            left - 5.0,
            y + 4.0,
        );
    }
    if ymin < 0.0 && ymax > 0.0 {
        let _ = writeln!(
            svg,
            r##"<path d="M{left} {:.1} H{:.1}" stroke="#bbbbbb"/>"##,
            sy(0.0),
            left + w
        );
    }
    let _ = writeln!(
        svg,
        r##"<text x="{:.1}" y="{:.1}" font-size="13" font-weight="bold" fill="#222222">{}</text>"##,
        left,
        y0 + 18.0,
        escape(&panel.title)
    );
    let _ = writeln!(
        svg,
        r##"<text x="{:.1}" y="{:.1}" font-size="11" text-anchor="middle" fill="#444444">{}</text>"##,
        left + w / 2.0,
        top + h + 30.0,
        panel.x_label
    );
    let _ = writeln!(
        svg,
        r##"<text transform="translate({:.1} {:.1}) rotate(-90)" font-size="11" text-anchor="middle" fill="#444444">{}</text>"##,
        x0 + 14.0,
        top + h / 2.0,
        panel.y_label
    );
    // Curves, clipped to the plot box.
    let clip = format!("clip{}_{}", x0 as i64, y0 as i64);
    let _ = writeln!(
        svg,
        r#"<clipPath id="{clip}"><rect x="{left}" y="{top}" width="{w}" height="{h}"/></clipPath><g clip-path="url(#{clip})">"#
    );
    for (s, &dots) in panel.series.iter().zip(&panel.markers) {
        if dots {
            for &(x, y) in &s.points {
                let _ = writeln!(
                    svg,
                    r#"<circle cx="{:.2}" cy="{:.2}" r="2.6" fill="{}"/>"#,
                    sx(x),
                    sy(y),
                    s.color
                );
            }
            continue;
        }
        let mut d = String::new();
        for (i, &(x, y)) in s.points.iter().enumerate() {
            let _ = write!(
                d,
                "{}{:.2} {:.2}",
                if i == 0 { "M" } else { " L" },
                sx(x),
                sy(y)
            );
        }
        let dash = if s.dashed {
            r#" stroke-dasharray="5 4""#
        } else {
            ""
        };
        let _ = writeln!(
            svg,
            r#"<path d="{d}" fill="none" stroke="{}" stroke-width="1.8" stroke-linejoin="round"{dash}/>"#,
            s.color
        );
    }
    svg.push_str("</g>\n");
    // Legend: a column to the right of the box.
    for (i, s) in labelled.iter().enumerate() {
        let ly = top + 8.0 + 16.0 * i as f64;
        let lx = left + w + 10.0;
        let dash = if s.dashed {
            r#" stroke-dasharray="5 4""#
        } else {
            ""
        };
        let _ = writeln!(
            svg,
            r##"<path d="M{lx:.1} {ly:.1} h18" stroke="{}" stroke-width="2"{dash}/><text x="{:.1}" y="{:.1}" font-size="11" fill="#222222">{}</text>"##,
            s.color,
            lx + 24.0,
            ly + 4.0,
            escape(&s.label)
        );
    }
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Lays panels out in a grid of `cols` columns and renders the figure to a PNG.
fn write_figure(path: &Path, title: &str, panels: &[Panel], cols: usize) -> Result<(), PlotError> {
    let rows = panels.len().div_ceil(cols);
    let (w, h) = (PANEL_W * cols as f64 + 20.0, PANEL_H * rows as f64 + 44.0);
    let mut svg = String::new();
    let _ = writeln!(
        svg,
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="DejaVu Sans, Liberation Sans, sans-serif"><rect width="{w}" height="{h}" fill="#ffffff"/>
<text x="14" y="26" font-size="16" font-weight="bold" fill="#111111">{}</text>"##,
        escape(title)
    );
    for (i, p) in panels.iter().enumerate() {
        draw_panel(
            &mut svg,
            p,
            10.0 + PANEL_W * (i % cols) as f64,
            40.0 + PANEL_H * (i / cols) as f64,
        );
    }
    svg.push_str("</svg>\n");
    let mut opt = usvg::Options::default();
    opt.fontdb_mut().load_system_fonts();
    let tree = usvg::Tree::from_str(&svg, &opt).map_err(|e| PlotError::Render(e.to_string()))?;
    let size = tree.size().to_int_size();
    let mut pixmap = resvg::tiny_skia::Pixmap::new(size.width(), size.height())
        .ok_or_else(|| PlotError::Render("empty figure".into()))?;
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::identity(),
        &mut pixmap.as_mut(),
    );
    let err = |e: String| PlotError::Io {
        path: path.display().to_string(),
        message: e,
    };
    let png = pixmap.encode_png().map_err(|e| err(e.to_string()))?;
    gmotion::atomic::write_bytes(path, &png).map_err(|e| err(e.to_string()))
}

/// Finite-difference velocity of uniformly sampled points (at the midpoints).
fn velocity(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    points
        .windows(2)
        .map(|w| {
            (
                0.5 * (w[0].0 + w[1].0),
                (w[1].1 - w[0].1) / (w[1].0 - w[0].0),
            )
        })
        .collect()
}

/// The interrupted step input of the first figure: `(time, target)` changes.
fn interrupted_input() -> Vec<(f64, f64)> {
    let mut changes = vec![(0.2, 1.0), (0.45, 0.2), (0.75, 0.8)];
    // A burst of retargets every 80 ms, like a dragged slider.
    for k in 0..10 {
        changes.push((1.6 + 0.08 * f64::from(k), 0.7 - 0.07 * f64::from(k)));
    }
    changes.push((2.8, 1.0));
    changes
}

/// Runs a continuous-time transition on `changes`, sampled at `rate` until `end`.
fn run_transition(
    tr: &mut dyn Transition<f64>,
    changes: &[(f64, f64)],
    rate: f64,
    end: f64,
) -> Vec<(f64, f64)> {
    let mut next = 0;
    (0..=(end * rate) as usize)
        .map(|i| {
            let t = i as f64 / rate;
            while next < changes.len() && changes[next].0 <= t {
                tr.retarget(changes[next].0, changes[next].1);
                next += 1;
            }
            (t, tr.sample(t))
        })
        .collect()
}

/// The input as a staircase of points.
fn staircase(changes: &[(f64, f64)], x0: f64, end: f64) -> Vec<(f64, f64)> {
    let mut pts = vec![(0.0, x0)];
    let mut v = x0;
    for &(t, x) in changes {
        pts.push((t, v));
        pts.push((t, x));
        v = x;
    }
    pts.push((end, v));
    pts
}

fn interrupted_figure(path: &Path) -> Result<(), PlotError> {
    let (rate, end, d) = (240.0, 4.0, 0.5);
    let changes = interrupted_input();
    let ease = Ease::new(Easing::CubicBezier([0.42, 0.0, 0.58, 1.0]), d)?;
    let simple = run_transition(
        &mut SimpleTransition::new(ease.clone(), 0.0),
        &changes,
        rate,
        end,
    );
    let spline = run_transition(&mut SplineTransition::new(d, 0.0)?, &changes, rate, end);
    let fir = run_transition(&mut FirTransition::new(ease, 0.0), &changes, rate, end);
    let spec = SmoothSpec::parse("spring(0.6, 0.1)")?;
    let input: Vec<f64> = (0..=(end * rate) as usize)
        .map(|i| {
            let t = i as f64 / rate;
            changes.iter().rev().find(|c| c.0 <= t).map_or(0.0, |c| c.1)
        })
        .collect();
    let spring: Vec<(f64, f64)> = smooth_samples(&spec, &input, rate)?
        .into_iter()
        .enumerate()
        .map(|(i, y)| (i as f64 / rate, y))
        .collect();
    let steps = staircase(&changes, 0.0, end);
    let rows: [(&str, &'static str, Curve); 4] = [
        (
            "Simple transitions (Alg. 1), ease-in-out 0.5 s",
            "#d62728",
            simple,
        ),
        ("Spline transitions (sec. 3), 0.5 s", "#9467bd", spline),
        (
            "FIR transitions (Alg. 2), ease-in-out 0.5 s",
            "#1f77b4",
            fir,
        ),
        (
            "Spring, duration 0.6 s, bounce 0.1 (ZOH biquads)",
            "#2ca02c",
            spring,
        ),
    ];
    let mut panels = Vec::new();
    for (title, color, pts) in rows {
        panels.push(
            Panel::new(title, "time (s)", "position")
                .line(Series::new("", "#888888", steps.clone()).dashed())
                .line(Series::new("", color, pts.clone())),
        );
        panels.push(
            Panel::new("velocity", "time (s)", "units / s").line(Series::new(
                "",
                color,
                velocity(&pts),
            )),
        );
    }
    write_figure(
        path,
        "Interrupted transitions: position (left, dashed: target) and velocity (right)",
        &panels,
        2,
    )
}

fn stall_figure(path: &Path) -> Result<(), PlotError> {
    let (rate, end) = (600.0, 3.0);
    let ease = Ease::new(Easing::CubicBezier([0.42, 0.0, 0.58, 1.0]), 0.5)?;
    let ramp = |t: f64| t.min(2.0);
    let colors = ["#1f77b4", "#ff7f0e", "#d62728"];
    let mut simple_panel = Panel::new("Simple transitions (Alg. 1)", "time (s)", "position");
    let mut fir_panel = Panel::new("FIR transitions (Alg. 2)", "time (s)", "position");
    let target: Vec<(f64, f64)> = (0..=300)
        .map(|i| (f64::from(i) / 100.0, ramp(f64::from(i) / 100.0)))
        .collect();
    simple_panel = simple_panel.line(Series::new("target", "#888888", target.clone()).dashed());
    fir_panel = fir_panel.line(Series::new("target", "#888888", target).dashed());
    for (hz, color) in [5.0, 20.0, 80.0].into_iter().zip(colors) {
        let changes: Vec<(f64, f64)> = (1..=(2.0 * hz) as usize)
            .map(|k| (k as f64 / hz, ramp(k as f64 / hz)))
            .collect();
        let s = run_transition(
            &mut SimpleTransition::new(ease.clone(), 0.0),
            &changes,
            rate,
            end,
        );
        let f = run_transition(
            &mut FirTransition::new(ease.clone(), 0.0),
            &changes,
            rate,
            end,
        );
        let label = format!("retarget at {hz} Hz");
        simple_panel = simple_panel.line(Series::new(label.clone(), color, s));
        fir_panel = fir_panel.line(Series::new(label, color, f));
    }
    write_figure(
        path,
        "Claim 1: frequent retargeting stalls simple transitions",
        &[simple_panel, fir_panel],
        2,
    )
}

fn discretization_figure(path: &Path) -> Result<(), PlotError> {
    let fps = 15.0;
    let spring = Spring::from_duration_bounce(0.5, 0.4)?;
    let exact: Vec<(f64, f64)> = (0..=600)
        .map(|i| f64::from(i) / 400.0)
        .map(|t| (t, spring.step_state(t).0))
        .collect();
    let lti = Lti::spring(&spring);
    let methods = [
        (Discretization::ZeroOrderHold, "zero-order hold", "#1f77b4"),
        (
            Discretization::ImpulseInvariant,
            "impulse invariance",
            "#ff7f0e",
        ),
        (Discretization::Bilinear, "bilinear (Tustin)", "#d62728"),
        (Discretization::Matched, "matched z", "#9467bd"),
    ];
    let mut panels = Vec::new();
    for (m, name, color) in methods {
        let mut sys = lti.discretize::<f64>(m, fps)?;
        sys.reset(0.0);
        let pts: Vec<(f64, f64)> = (0..=(1.5 * fps) as usize)
            .map(|n| (n as f64 / fps, sys.step(1.0)))
            .collect();
        panels.push(
            Panel::new(format!("{name} at {fps} fps"), "time (s)", "position")
                .line(Series::new("continuous", "#888888", exact.clone()))
                .dots(Series::new(name, color, pts)),
        );
    }
    write_figure(
        path,
        "Spring (duration 0.5 s, bounce 0.4): unit step response, discretised",
        &panels,
        2,
    )
}

fn easing_figure(path: &Path) -> Result<(), PlotError> {
    let curves: [(&str, Easing, &'static str); 6] = [
        ("bspline(1) = linear", Easing::BSpline(1), "#aaaaaa"),
        ("bspline(2)", Easing::BSpline(2), "#9ecae1"),
        ("bspline(3)", Easing::BSpline(3), "#4292c6"),
        ("bspline(6)", Easing::BSpline(6), "#08306b"),
        ("poles(2)", Easing::poles(2)?, "#fd8d3c"),
        ("poles(4)", Easing::poles(4)?, "#d94801"),
    ];
    let mut pos = Panel::new("Easing s(u)", "u", "s");
    let mut vel = Panel::new("Velocity s'(u)", "u", "ds/du");
    for (name, e, color) in curves {
        let pts: Vec<(f64, f64)> = (0..=400)
            .map(|i| f64::from(i) / 400.0)
            .map(|u| (u, e.apply(u)))
            .collect();
        vel = vel.line(Series::new(name, color, velocity(&pts)));
        pos = pos.line(Series::new(name, color, pts));
    }
    write_figure(
        path,
        "Easings from filters: B-spline windows and pole cascades (sec. 9)",
        &[pos, vel],
        2,
    )
}

/// Writes the transition plots into `out_dir` (created if missing) and returns their
/// paths.
pub fn transition_plots(out_dir: &Path) -> Result<Vec<PathBuf>, PlotError> {
    std::fs::create_dir_all(out_dir).map_err(|e| PlotError::Io {
        path: out_dir.display().to_string(),
        message: e.to_string(),
    })?;
    let figures: [(&str, Figure); 4] = [
        ("transitions_interrupted.png", interrupted_figure),
        ("transitions_stall.png", stall_figure),
        ("spring_discretizations.png", discretization_figure),
        ("easings.png", easing_figure),
    ];
    let mut out = Vec::new();
    for (name, draw) in figures {
        let path = out_dir.join(name);
        draw(&path)?;
        out.push(path);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round() {
        assert_eq!(tick_step(4.0), 1.0);
        assert_eq!(tick_step(0.9), 0.2);
        assert_eq!(tick_step(37.0), 10.0);
        assert_eq!(fmt_tick(-1e-17, 0.2), "0.0");
        assert_eq!(fmt_tick(-0.4, 0.2), "-0.4");
    }

    #[test]
    fn plots_are_written_as_png() {
        let dir = std::env::temp_dir().join(format!("gmotion-plots-{}", std::process::id()));
        let files = transition_plots(&dir).unwrap();
        assert_eq!(files.len(), 4);
        for f in &files {
            let bytes = std::fs::read(f).unwrap();
            assert_eq!(&bytes[1..4], b"PNG", "{}", f.display());
            assert!(
                bytes.len() > 10_000,
                "{} is suspiciously small",
                f.display()
            );
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
