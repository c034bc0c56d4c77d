//! TARGETS files: over time, new target values for attributes of tagged shapes, and the
//! systems that smooth them. Two spellings, JSON and CSV; `docs/transitions.md` is the
//! reference.

use std::fmt::Write as _;

use serde_json::Value;

use super::TransitionError;
use crate::color::Color;
use crate::signals::SmoothSpec;

/// An attribute a target can set: one axis of the 2-D position channel, or a whole
/// one-dimensional (or colour) channel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Attr {
    /// Canvas x of the shape's anchor (absolute).
    X,
    /// Canvas y of the shape's anchor (absolute).
    Y,
    /// Horizontal offset from where the shape is drawn.
    Dx,
    /// Vertical offset from where the shape is drawn.
    Dy,
    /// A channel other than [`Channel::Position`], set whole under its own name.
    Whole(Channel),
}

/// A smoothed channel: attributes that share one signal. `x`, `y`, `dx` and `dy` are the
/// two components of one 2-D position channel, so that matrix systems such as `arc` can
/// mix them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Channel {
    /// Offset `(dx, dy)` of the anchor (2-D).
    Position,
    /// Uniform scale.
    Scale,
    /// Horizontal scale.
    Sx,
    /// Vertical scale.
    Sy,
    /// Horizontal zoom.
    Zx,
    /// Vertical zoom.
    Zy,
    /// Rotation in degrees.
    Rotate,
    /// Opacity.
    Opacity,
    /// Fill tint `(r·w, g·w, b·w, w)` (4-D).
    Fill,
}

impl Attr {
    /// The position attributes with their spellings.
    const AXES: [(Attr, &'static str); 4] = [
        (Attr::X, "x"),
        (Attr::Y, "y"),
        (Attr::Dx, "dx"),
        (Attr::Dy, "dy"),
    ];

    /// Parses a spelling: an axis, or the name of a channel other than position.
    pub fn parse(name: &str) -> Option<Attr> {
        let axis = Attr::AXES.iter().find(|(_, n)| *n == name).map(|(a, _)| *a);
        axis.or_else(|| {
            Channel::parse(name)
                .filter(|c| *c != Channel::Position)
                .map(Attr::Whole)
        })
    }

    /// The spelling.
    pub fn name(self) -> &'static str {
        match self {
            Attr::Whole(c) => c.name(),
            axis => Attr::AXES
                .iter()
                .find(|(a, _)| *a == axis)
                .map_or("?", |(_, n)| n),
        }
    }

    /// The channel the attribute drives.
    pub fn channel(self) -> Channel {
        match self {
            Attr::X | Attr::Y | Attr::Dx | Attr::Dy => Channel::Position,
            Attr::Whole(c) => c,
        }
    }
}

impl Channel {
    /// Every channel with its spelling in `systems` keys.
    pub const ALL: [(Channel, &'static str); 9] = [
        (Channel::Position, "xy"),
        (Channel::Scale, "scale"),
        (Channel::Sx, "sx"),
        (Channel::Sy, "sy"),
        (Channel::Zx, "zx"),
        (Channel::Zy, "zy"),
        (Channel::Rotate, "rotate"),
        (Channel::Opacity, "opacity"),
        (Channel::Fill, "fill"),
    ];

    /// Parses a `systems` key spelling.
    pub fn parse(name: &str) -> Option<Channel> {
        Channel::ALL
            .iter()
            .find(|(_, n)| *n == name)
            .map(|(c, _)| *c)
    }

    /// The spelling.
    pub fn name(self) -> &'static str {
        Channel::ALL
            .iter()
            .find(|(c, _)| *c == self)
            .map_or("?", |(_, n)| n)
    }
}

/// A target value: a number, or a colour for `fill`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TargetValue {
    /// A number.
    Number(f64),
    /// A colour.
    Color(Color),
}

/// One change of target: at `time`, attribute `attr` of the shapes selected by `tag` and
/// `id` should move towards `value`.
#[derive(Clone, Debug, PartialEq)]
pub struct Target {
    /// Seconds from the start; targets at `time ≤ 0` set the starting state (at rest).
    pub time: f64,
    /// Shape tag (`all` selects every shape).
    pub tag: String,
    /// The shape's id within its tag; `None` selects every shape with the tag.
    pub id: Option<usize>,
    /// The attribute.
    pub attr: Attr,
    /// The new target value.
    pub value: TargetValue,
    /// Where the target was written (`line 12`, `targets[3]`), for error messages.
    pub location: String,
}

/// A system for one channel, on every shape or on the shapes of one tag.
#[derive(Clone, Debug, PartialEq)]
pub struct SystemOverride {
    /// Restrict to this tag (`None`: every shape).
    pub tag: Option<String>,
    /// The channel.
    pub channel: Channel,
    /// The system.
    pub system: SmoothSpec,
}

/// Frames per second when neither the command line nor the file names a rate: smooth
/// enough for the springs and filters transitions run through.
pub const DEFAULT_FPS: f64 = 60.0;

/// A parsed TARGETS file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Targets {
    /// The default system named in the file, if any.
    pub system: Option<SmoothSpec>,
    /// Per-channel systems, most specific first when looked up.
    pub systems: Vec<SystemOverride>,
    /// Frame rate named in the file.
    pub fps: Option<f64>,
    /// Duration named in the file (seconds).
    pub duration: Option<f64>,
    /// Per-tag anchors as fractions of the shape's bounding box (`[0.5, 1]`: bottom
    /// centre); shapes of other tags use their centroid.
    pub anchors: Vec<(String, [f64; 2])>,
    /// The targets, sorted by time (stable).
    pub targets: Vec<Target>,
}

impl Targets {
    /// Parses JSON or CSV, choosing by the first non-blank character (`{` or `[` is JSON).
    pub fn parse(text: &str) -> Result<Targets, TransitionError> {
        let first = text
            .trim_start_matches('\u{feff}')
            .trim_start()
            .chars()
            .next();
        if matches!(first, Some('{') | Some('[')) {
            Targets::from_json(text)
        } else {
            Targets::from_csv(text)
        }
    }

    /// Reads and parses a file (JSON or CSV by content).
    pub fn load(path: &std::path::Path) -> Result<Targets, TransitionError> {
        let text = crate::input::read_text(path, crate::input::DEFAULT_MAX_INPUT_BYTES)
            .map_err(crate::input::ReadError::at(path))?;
        Targets::parse(&text).map_err(|e| e.in_file(&path.display().to_string()))
    }

    /// The system for `channel` of a shape tagged `tag`: a tag-specific override, else a
    /// channel override, else `default`.
    pub fn system_for<'a>(
        &'a self,
        tag: &str,
        channel: Channel,
        default: &'a SmoothSpec,
    ) -> &'a SmoothSpec {
        self.systems
            .iter()
            .find(|o| o.channel == channel && o.tag.as_deref() == Some(tag))
            .or_else(|| {
                self.systems
                    .iter()
                    .find(|o| o.channel == channel && o.tag.is_none())
            })
            .map_or(default, |o| &o.system)
    }

    /// The frame rate to run at: `option` (the command line's `--fps`) if given, else the
    /// file's `fps`, else [`DEFAULT_FPS`].
    pub fn frame_rate(&self, option: Option<f64>) -> f64 {
        option.or(self.fps).unwrap_or(DEFAULT_FPS)
    }

    /// How long the animation runs without `--duration`: the last target's time or the
    /// file's own `duration`, whichever is later (what the `frames` limit is checked on
    /// before anything runs).
    pub fn end(&self) -> f64 {
        self.targets
            .iter()
            .map(|x| x.time)
            .chain(self.duration)
            .fold(0.0, f64::max)
    }

    /// The anchor fraction for a tag, if one is set.
    pub fn anchor_for(&self, tag: &str) -> Option<[f64; 2]> {
        self.anchors.iter().find(|(t, _)| t == tag).map(|a| a.1)
    }

    /// Parses the JSON spelling: an object `{fps?, duration?, system?, systems?, anchors?,
    /// targets}` or just the `targets` array.
    pub fn from_json(text: &str) -> Result<Targets, TransitionError> {
        let root: Value =
            serde_json::from_str(text.trim_start_matches('\u{feff}')).map_err(|e| {
                TransitionError::parse(
                    format!("line {}, column {}", e.line(), e.column()),
                    e.to_string(),
                )
            })?;
        let mut out = Targets::default();
        let list = match &root {
            Value::Array(items) => items,
            Value::Object(map) => {
                for key in map.keys() {
                    if !["fps", "duration", "system", "systems", "anchors", "targets"]
                        .contains(&key.as_str())
                    {
                        return Err(TransitionError::parse(
                            key.clone(),
                            "unknown key; expected fps, duration, system, systems, anchors or targets".into(),
                        ));
                    }
                }
                if let Some(v) = map.get("fps") {
                    out.fps = Some(json_number(v, "fps")?);
                }
                if let Some(v) = map.get("duration") {
                    out.duration = Some(json_number(v, "duration")?);
                }
                if let Some(v) = map.get("system") {
                    out.system = Some(parse_system(json_str(v, "system")?, "system")?);
                }
                if let Some(v) = map.get("systems") {
                    let systems = json_object(v, "systems", "channel: system")?;
                    for (key, spec) in systems {
                        let at = format!("systems.{key}");
                        out.systems
                            .push(parse_override(key, json_str(spec, &at)?, &at)?);
                    }
                }
                if let Some(v) = map.get("anchors") {
                    let anchors = json_object(v, "anchors", "tag: [fx, fy]")?;
                    for (tag, a) in anchors {
                        let at = format!("anchors.{tag}");
                        let pair = match a {
                            Value::Array(v) if v.len() == 2 => {
                                [json_number(&v[0], &at)?, json_number(&v[1], &at)?]
                            }
                            _ => {
                                return Err(TransitionError::parse(at, "expected [fx, fy]".into()));
                            }
                        };
                        out.anchors.push((tag.clone(), pair));
                    }
                }
                match map.get("targets") {
                    Some(Value::Array(items)) => items,
                    _ => {
                        return Err(TransitionError::parse(
                            "targets".into(),
                            "expected an array of targets".into(),
                        ));
                    }
                }
            }
            _ => {
                return Err(TransitionError::parse(
                    "top level".into(),
                    "expected an object or an array".into(),
                ));
            }
        };
        for (i, item) in list.iter().enumerate() {
            let at = format!("targets[{i}]");
            let Value::Object(t) = item else {
                return Err(TransitionError::parse(
                    at,
                    "expected an object {time, tag, id, attr, value}".into(),
                ));
            };
            for key in t.keys() {
                if !["time", "tag", "id", "attr", "value"].contains(&key.as_str()) {
                    return Err(TransitionError::parse(
                        at,
                        format!("unknown key `{key}`; expected time, tag, id, attr, value"),
                    ));
                }
            }
            let field = |k: &str| {
                t.get(k)
                    .ok_or_else(|| TransitionError::parse(at.clone(), format!("missing `{k}`")))
            };
            let time = json_number(field("time")?, &at)?;
            let tag = json_str(field("tag")?, &at)?.to_string();
            let id = match t.get("id") {
                None | Some(Value::Null) => None,
                Some(Value::String(s)) if s == "*" => None,
                Some(v) => Some(json_index(v, &at)?),
            };
            let attr_name = json_str(field("attr")?, &at)?;
            let attr = parse_attr(attr_name, &at)?;
            let value = match field("value")? {
                Value::String(s) => parse_value(attr, s, &at)?,
                v => parse_value(attr, &json_number(v, &at)?.to_string(), &at)?,
            };
            out.targets.push(Target {
                time,
                tag,
                id,
                attr,
                value,
                location: at,
            });
        }
        out.validate()?;
        Ok(out)
    }

    /// Parses the CSV spelling: a header naming the columns `time, tag, id, attr, value`
    /// (any order), one target per line, `#` comment lines, and `# key: value` directive
    /// lines for `fps`, `duration`, `system`, `system.<channel>`, `system.<tag>.<channel>`
    /// and `anchor.<tag>` (two numbers).
    pub fn from_csv(text: &str) -> Result<Targets, TransitionError> {
        let mut out = Targets::default();
        let mut columns: Option<[usize; 5]> = None;
        for (n, raw) in text.trim_start_matches('\u{feff}').lines().enumerate() {
            let at = format!("line {}", n + 1);
            let line = raw.trim();
            if line.is_empty() {
                continue;
            }
            if let Some(comment) = line.strip_prefix('#') {
                if let Some((key, value)) = comment.split_once(':') {
                    out.directive(key.trim(), value.trim(), &at)?;
                }
                continue;
            }
            let fields = split_csv(line, &at)?;
            let Some(cols) = columns else {
                let mut cols = [usize::MAX; 5];
                for (i, f) in fields.iter().enumerate() {
                    let slot = ["time", "tag", "id", "attr", "value"]
                        .iter()
                        .position(|c| *c == f.trim());
                    match slot {
                        Some(s) if cols[s] == usize::MAX => cols[s] = i,
                        _ => {
                            return Err(TransitionError::parse(
                                at,
                                format!(
                                    "header column `{f}`: expected each of time, tag, id, attr, value once"
                                ),
                            ));
                        }
                    }
                }
                if cols.contains(&usize::MAX) {
                    return Err(TransitionError::parse(
                        at,
                        "the header must name time, tag, id, attr and value".into(),
                    ));
                }
                columns = Some(cols);
                continue;
            };
            if fields.len() != 5 {
                return Err(TransitionError::parse(
                    at,
                    format!("expected 5 fields, found {}", fields.len()),
                ));
            }
            let get = |i: usize| fields[cols[i]].trim();
            let time = get(0).parse::<f64>().map_err(|_| {
                TransitionError::parse(at.clone(), format!("time `{}` is not a number", get(0)))
            })?;
            let id = match get(2) {
                "" | "*" => None,
                s => Some(s.parse::<usize>().map_err(|_| {
                    TransitionError::parse(
                        at.clone(),
                        format!("id `{s}` is not a whole number (or `*` for all)"),
                    )
                })?),
            };
            let attr = parse_attr(get(3), &at)?;
            let value = parse_value(attr, get(4), &at)?;
            out.targets.push(Target {
                time,
                tag: get(1).to_string(),
                id,
                attr,
                value,
                location: at,
            });
        }
        if columns.is_none() {
            return Err(TransitionError::parse(
                "line 1".into(),
                "no header line `time,tag,id,attr,value`".into(),
            ));
        }
        out.validate()?;
        Ok(out)
    }

    fn directive(&mut self, key: &str, value: &str, at: &str) -> Result<(), TransitionError> {
        let number = |v: &str| {
            v.parse::<f64>().map_err(|_| {
                TransitionError::parse(at.into(), format!("`{key}` needs a number, got `{v}`"))
            })
        };
        match key {
            "fps" => self.fps = Some(number(value)?),
            "duration" => self.duration = Some(number(value)?),
            "system" => self.system = Some(parse_system(value, at)?),
            _ => {
                if let Some(rest) = key.strip_prefix("system.") {
                    self.systems.push(parse_override(rest, value, at)?);
                } else if let Some(tag) = key.strip_prefix("anchor.") {
                    let nums: Vec<&str> = value
                        .split(|c: char| c == ',' || c.is_whitespace())
                        .filter(|s| !s.is_empty())
                        .collect();
                    if nums.len() != 2 {
                        return Err(TransitionError::parse(
                            at.into(),
                            "an anchor needs two numbers fx fy".into(),
                        ));
                    }
                    self.anchors
                        .push((tag.to_string(), [number(nums[0])?, number(nums[1])?]));
                } else {
                    return Err(TransitionError::parse(
                        at.into(),
                        format!(
                            "unknown directive `{key}`; expected fps, duration, system, system.<channel>, anchor.<tag>"
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    fn validate(&mut self) -> Result<(), TransitionError> {
        if let Some(f) = self.fps
            && !(f.is_finite() && f > 0.0 && f <= 1000.0)
        {
            return Err(TransitionError::parse(
                "fps".into(),
                format!("must lie in (0, 1000], got {f}"),
            ));
        }
        if let Some(d) = self.duration
            && !(d.is_finite() && d > 0.0)
        {
            return Err(TransitionError::parse(
                "duration".into(),
                format!("must be a positive number, got {d}"),
            ));
        }
        for (tag, a) in &self.anchors {
            if !a.iter().all(|v| v.is_finite()) {
                return Err(TransitionError::parse(
                    format!("anchor of `{tag}`"),
                    "must be finite".into(),
                ));
            }
        }
        for t in &self.targets {
            if !t.time.is_finite() {
                return Err(TransitionError::parse(
                    t.location.clone(),
                    format!("time {} is not finite", t.time),
                ));
            }
        }
        self.targets.sort_by(|a, b| a.time.total_cmp(&b.time));
        // A fixed order, whatever the spelling listed them in (lookups do not depend on it).
        self.systems
            .sort_by(|a, b| (&a.tag, a.channel).cmp(&(&b.tag, b.channel)));
        Ok(())
    }

    /// Writes the JSON spelling, one target per line.
    pub fn to_json(&self) -> String {
        let q = |s: &str| serde_json::to_string(s).unwrap_or_default();
        let mut out = String::from("{\n");
        if let Some(f) = self.fps {
            let _ = writeln!(out, "  \"fps\": {f},");
        }
        if let Some(d) = self.duration {
            let _ = writeln!(out, "  \"duration\": {d},");
        }
        if let Some(s) = &self.system {
            let _ = writeln!(out, "  \"system\": {},", q(&s.to_string()));
        }
        if !self.systems.is_empty() {
            let items: Vec<String> = self
                .systems
                .iter()
                .map(|o| {
                    let key = match &o.tag {
                        Some(t) => format!("{t}.{}", o.channel.name()),
                        None => o.channel.name().to_string(),
                    };
                    format!("{}: {}", q(&key), q(&o.system.to_string()))
                })
                .collect();
            let _ = writeln!(out, "  \"systems\": {{{}}},", items.join(", "));
        }
        if !self.anchors.is_empty() {
            let items: Vec<String> = self
                .anchors
                .iter()
                .map(|(t, [x, y])| format!("{}: [{x}, {y}]", q(t)))
                .collect();
            let _ = writeln!(out, "  \"anchors\": {{{}}},", items.join(", "));
        }
        out.push_str("  \"targets\": [\n");
        for (i, t) in self.targets.iter().enumerate() {
            let id = t.id.map_or("\"*\"".to_string(), |i| i.to_string());
            let value = match t.value {
                TargetValue::Number(v) => format!("{}", round6(v)),
                TargetValue::Color(c) => q(&c.to_hex()),
            };
            let _ = write!(
                out,
                "    {{\"time\": {}, \"tag\": {}, \"id\": {id}, \"attr\": \"{}\", \"value\": {value}}}",
                round6(t.time),
                q(&t.tag),
                t.attr.name()
            );
            out.push_str(if i + 1 < self.targets.len() {
                ",\n"
            } else {
                "\n"
            });
        }
        out.push_str("  ]\n}\n");
        out
    }
}

/// Rounds to 6 decimals for compact files (sub-micro-unit precision is noise here).
fn round6(v: f64) -> f64 {
    (v * 1e6).round() / 1e6
}

fn parse_system(text: &str, at: &str) -> Result<SmoothSpec, TransitionError> {
    SmoothSpec::parse(text)
        .map_err(|e| TransitionError::parse(at.into(), format!("system `{text}`: {e}")))
}

fn parse_override(key: &str, text: &str, at: &str) -> Result<SystemOverride, TransitionError> {
    let (tag, channel) = match key.rsplit_once('.') {
        Some((tag, ch)) => (Some(tag.to_string()), ch),
        None => (None, key),
    };
    let channel = Channel::parse(channel).ok_or_else(|| {
        let hint = if Attr::parse(channel).is_some_and(|a| a.channel() == Channel::Position) {
            "; x, y, dx and dy share the 2-D channel `xy`"
        } else {
            ""
        };
        TransitionError::parse(
            at.into(),
            format!("unknown channel `{channel}`; expected xy, scale, sx, sy, zx, zy, rotate, opacity, fill{hint}"),
        )
    })?;
    Ok(SystemOverride {
        tag,
        channel,
        system: parse_system(text, at)?,
    })
}

fn parse_attr(name: &str, at: &str) -> Result<Attr, TransitionError> {
    Attr::parse(name).ok_or_else(|| {
        TransitionError::parse(
            at.into(),
            format!("unknown attr `{name}`; expected x, y, dx, dy, scale, sx, sy, zx, zy, rotate, opacity, fill"),
        )
    })
}

fn parse_value(attr: Attr, text: &str, at: &str) -> Result<TargetValue, TransitionError> {
    if attr == Attr::Whole(Channel::Fill) {
        return Color::parse(text).map(TargetValue::Color).ok_or_else(|| {
            TransitionError::parse(
                at.into(),
                format!("fill value `{text}` is not a colour (#rrggbb or a CSS name)"),
            )
        });
    }
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(TargetValue::Number(v)),
        _ => Err(TransitionError::parse(
            at.into(),
            format!("{} value `{text}` is not a finite number", attr.name()),
        )),
    }
}

fn json_number(v: &Value, at: &str) -> Result<f64, TransitionError> {
    v.as_f64()
        .ok_or_else(|| TransitionError::parse(at.into(), format!("expected a number, got {v}")))
}

fn json_index(v: &Value, at: &str) -> Result<usize, TransitionError> {
    v.as_u64().map(|i| i as usize).ok_or_else(|| {
        TransitionError::parse(
            at.into(),
            format!("id must be a whole number or \"*\", got {v}"),
        )
    })
}

fn json_str<'a>(v: &'a Value, at: &str) -> Result<&'a str, TransitionError> {
    v.as_str()
        .ok_or_else(|| TransitionError::parse(at.into(), format!("expected a string, got {v}")))
}

/// `v` as a JSON object, or an error at `at` saying it should be one of `entries`.
fn json_object<'a>(
    v: &'a Value,
    at: &str,
    entries: &str,
) -> Result<&'a serde_json::Map<String, Value>, TransitionError> {
    v.as_object().ok_or_else(|| {
        TransitionError::parse(at.into(), format!("expected an object of {entries}"))
    })
}

/// Splits one CSV line on commas, honouring double-quoted fields (`""` is a quote).
fn split_csv(line: &str, at: &str) -> Result<Vec<String>, TransitionError> {
    let mut fields = Vec::new();
    let mut cur = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                cur.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => fields.push(std::mem::take(&mut cur)),
            _ => cur.push(c),
        }
    }
    if quoted {
        return Err(TransitionError::parse(
            at.into(),
            "unterminated quoted field".into(),
        ));
    }
    fields.push(cur);
    Ok(fields)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_and_csv_say_the_same() {
        let json = r##"{
            "fps": 30, "system": "spring(0.5, 0)",
            "systems": {"zy": "none", "brush.xy": "fir(linear, 0.1)"},
            "anchors": {"bar": [0.5, 1]},
            "targets": [
                {"time": 1.5, "tag": "bar", "id": 2, "attr": "sy", "value": 0.4},
                {"time": 0.5, "tag": "dot", "id": "*", "attr": "fill", "value": "#ff0000"},
                {"time": 0.5, "tag": "dot", "attr": "x", "value": 120}
            ]}"##;
        let csv = "# fps: 30\n# system: spring(0.5, 0)\n# system.zy: none\n# system.brush.xy: fir(linear, 0.1)\n\
                   # anchor.bar: 0.5 1\ntime,tag,id,attr,value\n1.5,bar,2,sy,0.4\n0.5,dot,*,fill,#ff0000\n0.5,dot,,x,120\n";
        let a = Targets::from_json(json).unwrap();
        let b = Targets::from_csv(csv).unwrap();
        assert_eq!(a.targets.len(), 3);
        assert_eq!(
            a.targets[0].attr,
            Attr::Whole(Channel::Fill),
            "sorted by time"
        );
        for (x, y) in a.targets.iter().zip(&b.targets) {
            assert_eq!(
                (x.time, &x.tag, x.id, x.attr, x.value),
                (y.time, &y.tag, y.id, y.attr, y.value)
            );
        }
        assert_eq!(
            (a.fps, &a.system, &a.systems, &a.anchors),
            (b.fps, &b.system, &b.systems, &b.anchors)
        );
        let again = Targets::parse(&a.to_json()).unwrap();
        assert_eq!(again.targets.len(), 3);
        assert_eq!(again.systems, a.systems);
        let default = SmoothSpec::Identity;
        assert_eq!(
            a.system_for("brush", Channel::Position, &default)
                .to_string(),
            "fir(linear, 0.1)"
        );
        assert_eq!(a.system_for("dot", Channel::Position, &default), &default);
    }

    #[test]
    fn errors_name_the_place() {
        let cases = [
            (
                "[{\"time\": 1, \"tag\": \"a\", \"attr\": \"wobble\", \"value\": 1}]",
                "targets[0]: unknown attr `wobble`",
            ),
            (
                "[{\"time\": 1, \"tag\": \"a\", \"attr\": \"x\"}]",
                "targets[0]: missing `value`",
            ),
            (
                "{\"targets\": [], \"system\": \"spring(0.5, 2)\"}",
                "bounce",
            ),
            (
                "{\"targets\": [], \"systems\": {\"x\": \"none\"}}",
                "share the 2-D channel `xy`",
            ),
            ("{\"targets\": [}", "line 1, column"),
            (
                "time,tag,id,attr,value\n1,a,0,fill,notacolour\n",
                "line 2: fill value",
            ),
            (
                "time,tag,id,attr,value\n1,a,zero,x,3\n",
                "line 2: id `zero`",
            ),
            ("time,tag,attr,value\n", "header"),
            ("# fps: fast\ntime,tag,id,attr,value\n", "line 1"),
            ("{\"fps\": 0, \"targets\": []}", "fps"),
        ];
        crate::testing::assert_refused(&cases, Targets::parse);
    }
}
