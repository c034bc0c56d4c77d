//! Where shape tags come from, and how layer names become tags.
//!
//! Design tools name layers with ids (`<g id="Wheel_2">`) and make them unique with a
//! counter. A counter that only tells copies apart is noise to a grammar author, so
//! [`strip_counter_among`] removes Illustrator's copy suffix (`eye_1_`) and Figma's copy
//! numbers (`Vector_2` beside `Vector`), but keeps names whose number is all that tells
//! distinct layers apart (`Layer_1`, `Layer_2`). Which attributes are read is [`TagFrom`].
//!
//! A class names a shape only when a designer chose it: the style classes design tools
//! generate (Illustrator's `st0` and `cls-1`, CorelDRAW's `fil0`, `str1`, `fnt0`; the list
//! is [`GENERATED_CLASSES`]) are skipped by [`first_named_class`], so an Illustrator
//! export's shapes are named by their layers (`letter_G`), not by their colours (`st1`).

pub use gmotion::tagging::{GENERATED_CLASSES, TagFrom, is_generated_class};

/// Removes a trailing layer counter (shared with the other importers; see
/// [`gmotion::tagging::strip_counter`]).
///
/// ```
/// use gmotion_import_svg::tags::strip_counter;
/// assert_eq!(strip_counter("Wheel_2"), "Wheel");
/// ```
pub use gmotion::tagging::{strip_counter, strip_counter_among};

/// The first class name of a `class` attribute value, if any.
pub fn first_class(value: &str) -> Option<&str> {
    value.split_ascii_whitespace().next()
}

/// The first class name of a `class` attribute value that is not a generated style class
/// ([`is_generated_class`]): `st0 hero` is named `hero`, `st0 st1` not at all.
///
/// ```
/// use gmotion_import_svg::tags::first_named_class;
/// assert_eq!(first_named_class("st0 hero"), Some("hero"));
/// assert_eq!(first_named_class("fil0 str1"), None);
/// ```
pub fn first_named_class(value: &str) -> Option<&str> {
    value
        .split_ascii_whitespace()
        .find(|c| !is_generated_class(c))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counters_are_removed_only_at_the_end() {
        assert_eq!(strip_counter("Layer_1"), "Layer");
        assert_eq!(strip_counter("a_1_b"), "a_1_b");
        assert_eq!(strip_counter("x2"), "x2");
        assert_eq!(strip_counter("x_"), "x_");
        assert_eq!(strip_counter("wheel__3"), "wheel_");
        assert_eq!(strip_counter(""), "");
    }

    #[test]
    fn first_class_skips_whitespace() {
        assert_eq!(first_class("  hero big "), Some("hero"));
        assert_eq!(first_class("   "), None);
    }

    #[test]
    fn named_classes_skip_the_generated_ones() {
        assert_eq!(first_named_class("st1"), None);
        assert_eq!(first_named_class("cls-1 cls-2"), None);
        assert_eq!(first_named_class("st2 st3 title"), Some("title"));
        assert_eq!(first_named_class("wheel st0"), Some("wheel"));
        assert_eq!(first_named_class("fil0 str2 fnt1"), None);
        assert_eq!(first_named_class("node3"), Some("node3"));
        assert_eq!(first_named_class(""), None);
    }
}
