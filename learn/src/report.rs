//! The report: each unit's largest error, the rule sets and the units each covers, and
//! what could not be explained (kept as plain per-unit rules, never dropped).

use std::fmt;

use gmotion::scene::Scene;
use gmotion_pipeline::LottieSource;
use serde_json::Value;

use crate::Options;
use crate::fit::{Clock, Fitted};
use crate::rules::RuleSet;
use crate::sample::UnitSamples;

/// One unit's line of the report.
#[derive(Clone, Debug)]
pub struct UnitReport {
    /// Its tag and id (`c:2`).
    pub name: String,
    /// Its largest error over every frame, in pixels.
    pub max_px: f64,
    /// Its largest opacity error.
    pub max_opacity: f64,
    /// How many slices its timeline has.
    pub slices: usize,
    /// Why it is not reproduced within the tolerance, when it is not.
    pub unexplained: Option<String>,
}

/// What `learn` tells: per unit errors, the rule sets, what it could not explain.
#[derive(Clone, Debug)]
pub struct Report {
    /// One line per unit, in scene order.
    pub units: Vec<UnitReport>,
    /// The grammar's rule sets.
    pub sets: Vec<RuleSet>,
    /// Layers using what `learn` does not model (expressions, time remapping), named.
    pub unmodelled: Vec<String>,
    /// The tolerance in pixels.
    pub tolerance: f64,
    /// Frames sampled per unit.
    pub frames: usize,
    /// Frames per second.
    pub fps: f64,
}

impl Report {
    /// The report of a learned animation.
    pub fn new(
        still: &Scene,
        fitted: &[Fitted],
        sets: Vec<RuleSet>,
        unmodelled: &[String],
        samples: &[UnitSamples],
        opts: &Options,
        clock: Clock,
    ) -> Report {
        let units = still
            .shapes
            .iter()
            .zip(fitted)
            .zip(samples)
            .map(|((s, f), smp)| {
                let mut why = Vec::new();
                if smp.inner_px > opts.tolerance {
                    why.push(if smp.inner_px.is_finite() {
                        format!(
                            "its drawing changes inside the layer (paths or inner layers move up to {:.2} px), which `learn` does not model yet",
                            smp.inner_px
                        )
                    } else {
                        "its drawing changes structure between frames".to_string()
                    });
                }
                if f.max_opacity > opts.opacity_tolerance {
                    let first = smp.opacity.first().copied().unwrap_or(1.0);
                    let most = smp.opacity.iter().copied().fold(0.0, f64::max);
                    why.push(if first <= 0.0 && most > 0.0 {
                        "it is hidden at frame 0 and appears later, which an opacity factor on the still cannot raise".to_string()
                    } else if most > first + opts.opacity_tolerance {
                        format!("it is more opaque later ({most:.2}) than at frame 0 ({first:.2}), which an opacity factor on the still cannot raise")
                    } else {
                        format!("opacity or fill off by up to {:.3}", f.max_opacity)
                    });
                }
                if f.max_px > opts.tolerance && why.is_empty() {
                    why.push(format!("motion off by up to {:.2} px", f.max_px));
                }
                if smp.stroke_changes {
                    why.push("its stroke changes in a way `learn` does not fit within the tolerance (its opacity, a stroke appearing or going, or a stroke change beside a morph)".to_string());
                }
                let fills = smp.fill.iter().filter_map(|c| *c).collect::<Vec<_>>();
                if !smp.one_fill
                    && fills.windows(2).any(|w| {
                        w[0].iter().zip(&w[1]).any(|(a, b)| (a - b).abs() > 1.0 / 255.0)
                    })
                {
                    why.push("its fills change colour but it paints several colours, which one fill change cannot say".to_string());
                }
                UnitReport {
                    name: format!("{}:{}", s.tag, s.id),
                    max_px: f.max_px,
                    max_opacity: f.max_opacity,
                    slices: f.slices.len(),
                    unexplained: (!why.is_empty()).then(|| why.join("; ")),
                }
            })
            .collect();
        Report {
            units,
            sets,
            unmodelled: unmodelled.to_vec(),
            tolerance: opts.tolerance,
            frames: samples.first().map_or(0, |s| s.motion.len()),
            fps: clock.fps,
        }
    }

    /// Marks unit `u` as not explained, for `why` (added to what was found already).
    pub fn explain(&mut self, u: usize, why: String) {
        if let Some(r) = self.units.get_mut(u) {
            r.unexplained = Some(match r.unexplained.take() {
                Some(w) => format!("{w}; {why}"),
                None => why,
            });
        }
    }

    /// How many rules the grammar has.
    pub fn rule_count(&self) -> usize {
        self.sets.iter().map(|s| s.rules).sum()
    }

    /// The units not reproduced within the tolerance.
    pub fn unexplained(&self) -> impl Iterator<Item = &UnitReport> {
        self.units.iter().filter(|u| u.unexplained.is_some())
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "learned {} units over {} frames at {} fps: {} rules in {} rule sets (tolerance {} px)",
            self.units.len(),
            self.frames,
            self.fps,
            self.rule_count(),
            self.sets.len(),
            self.tolerance
        )?;
        writeln!(f, "rule sets:")?;
        for s in &self.sets {
            let names: Vec<&str> = s
                .units
                .iter()
                .filter_map(|&u| self.units.get(u).map(|r| r.name.as_str()))
                .collect();
            write!(
                f,
                "  [{}] {} rules, covers {}",
                s.tags,
                s.rules,
                names.join(" ")
            )?;
            if let Some(st) = &s.stagger {
                write!(f, " (stagger: offset {st})")?;
            }
            writeln!(f)?;
        }
        writeln!(f, "units (max error px, max opacity error, slices):")?;
        for u in &self.units {
            write!(
                f,
                "  {}  {:.3} px  {:.4}  {} slices",
                u.name, u.max_px, u.max_opacity, u.slices
            )?;
            if let Some(w) = &u.unexplained {
                write!(f, "  NOT EXPLAINED: {w}")?;
            }
            writeln!(f)?;
        }
        if !self.unmodelled.is_empty() {
            writeln!(
                f,
                "not modelled (kept as plain per-unit motion, as sampled):"
            )?;
            for m in &self.unmodelled {
                writeln!(f, "  {m}")?;
            }
        }
        let bad = self.unexplained().count();
        if bad == 0 {
            writeln!(f, "every unit within the tolerance")
        } else {
            writeln!(
                f,
                "{bad} units not explained within the tolerance (see above)"
            )
        }
    }
}

/// The layers of `src` that use expressions or time remapping, named with their place.
pub fn unmodelled(src: &LottieSource) -> Vec<String> {
    fn has_expression(v: &Value) -> bool {
        match v {
            Value::Object(o) => {
                o.get("x").is_some_and(Value::is_string) || o.values().any(has_expression)
            }
            Value::Array(a) => a.iter().any(has_expression),
            _ => false,
        }
    }
    let mut out = Vec::new();
    let mut visit = |layers: &[Value], at: &str| {
        for (i, l) in layers.iter().enumerate() {
            let name = l.get("nm").and_then(Value::as_str).unwrap_or("");
            if l.get("tm").is_some() {
                out.push(format!("{at}[{i}] \"{name}\": time remapping"));
            }
            if has_expression(l) {
                out.push(format!("{at}[{i}] \"{name}\": expressions"));
            }
        }
    };
    if let Some(layers) = src.json.get("layers").and_then(Value::as_array) {
        visit(layers, "$.layers");
    }
    if let Some(assets) = src.json.get("assets").and_then(Value::as_array) {
        for (k, a) in assets.iter().enumerate() {
            if let Some(layers) = a.get("layers").and_then(Value::as_array) {
                visit(layers, &format!("$.assets[{k}].layers"));
            }
        }
    }
    out
}
