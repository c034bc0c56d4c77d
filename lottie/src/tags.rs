//! Layer names as tags.
//!
//! After Effects names layers freely ("Left Arm", "Wheel 2") and Bodymovin appends
//! " Outlines" to shape layers converted from Illustrator art. A layer's tag is its name
//! without that suffix, made writable in a grammar ([`gmotion::tagging::grammar_name`])
//! and without its counter ([`gmotion::tagging::strip_counter`], as for SVG layer ids), so
//! every "Wheel 2" is a `Wheel`. Names After Effects gives by default ("Shape Layer 3",
//! "Null 1", "Pre-comp 2", "Dark Gray Solid 1") say nothing about the art: such layers are
//! tagged with their kind (`shape`, `precomp`, `solid`, `image`, `text`). With
//! `--units groups`, a shape layer's top-level groups are tagged the same way from their
//! own names ([`part_tag`]; "Group 2" gives `group`).

use gmotion::tagging::{grammar_name, strip_counter};

use crate::model::{LayerKind, ShapeKind};

/// Names After Effects gives new layers, before their counter.
const DEFAULT_NAMES: [&str; 6] = [
    "Shape Layer",
    "Null",
    "Pre-comp",
    "Comp",
    "Adjustment Layer",
    "Layer",
];

/// Whether `name` is one After Effects makes up ("Shape Layer 3", "White Solid 1").
pub fn is_default_name(name: &str) -> bool {
    let stem = name
        .trim()
        .trim_end_matches(|c: char| c.is_ascii_digit())
        .trim_end();
    stem.is_empty() || DEFAULT_NAMES.contains(&stem) || stem.ends_with(" Solid") || stem == "Solid"
}

/// The tag of a layer named `name` of kind `kind`.
///
/// ```
/// use gmotion_lottie::model::LayerKind;
/// use gmotion_lottie::tags::layer_tag;
/// assert_eq!(layer_tag("Wheel 2 Outlines", LayerKind::Shape), "Wheel");
/// assert_eq!(layer_tag("Left arm", LayerKind::Shape), "Left_arm");
/// assert_eq!(layer_tag("Shape Layer 3", LayerKind::Shape), "shape");
/// assert_eq!(layer_tag("Pre-comp 1", LayerKind::Precomp), "precomp");
/// assert_eq!(layer_tag("Dark Gray Solid 1", LayerKind::Solid), "solid");
/// assert_eq!(layer_tag("", LayerKind::Text), "text");
/// ```
pub fn layer_tag(name: &str, kind: LayerKind) -> String {
    let name = name.trim();
    let name = name.strip_suffix(" Outlines").unwrap_or(name).trim();
    if is_default_name(name) {
        return kind.name().to_string();
    }
    match grammar_name(name) {
        Some(n) => strip_counter(&n).to_string(),
        None => kind.name().to_string(),
    }
}

/// Names After Effects and Illustrator give new shape items, before their counter.
const DEFAULT_PART_NAMES: [&str; 8] = [
    "Group",
    "Shape",
    "Path",
    "Rectangle",
    "Ellipse",
    "Polystar",
    "Star",
    "Polygon",
];

/// The tag of a top-level shape item named `name` that is a unit of its own
/// (`--units groups`): as a layer's, with default names ("Group 3", "Rectangle 1") giving
/// the item's kind (`group`, `path`, `rect`, `ellipse`, `star`).
///
/// ```
/// use gmotion_lottie::model::ShapeKind;
/// use gmotion_lottie::tags::part_tag;
/// assert_eq!(part_tag("Left wheel 2", &ShapeKind::Group(vec![])), "Left_wheel");
/// assert_eq!(part_tag("Group 3", &ShapeKind::Group(vec![])), "group");
/// ```
pub fn part_tag(name: &str, kind: &ShapeKind) -> String {
    let kind = kind.part_name().unwrap_or("group");
    let stem = name
        .trim()
        .trim_end_matches(|c: char| c.is_ascii_digit())
        .trim_end();
    if stem.is_empty() || DEFAULT_PART_NAMES.contains(&stem) {
        return kind.to_string();
    }
    match grammar_name(name.trim()) {
        Some(n) => strip_counter(&n).to_string(),
        None => kind.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counters_and_defaults() {
        assert_eq!(layer_tag("eye_1", LayerKind::Shape), "eye");
        assert_eq!(layer_tag("eye-12", LayerKind::Shape), "eye");
        assert_eq!(layer_tag("Null 1", LayerKind::Null), "null");
        assert_eq!(layer_tag("Layer 4", LayerKind::Image), "image");
        assert_eq!(layer_tag("3 balls", LayerKind::Shape), "_3_balls");
        assert_eq!(layer_tag("img_0.png", LayerKind::Image), "img_0_png");
        assert_eq!(layer_tag("★", LayerKind::Shape), "shape");
        assert_eq!(
            layer_tag("Medium Gray-Royal Blue Solid 1", LayerKind::Solid),
            "solid"
        );
        assert_eq!(layer_tag("light 6", LayerKind::Shape), "light");
        assert_eq!(layer_tag("shape layer 2", LayerKind::Shape), "shape_layer");
    }
}
