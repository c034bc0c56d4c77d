//! Where shape tags come from, and how layer names become tags.
//!
//! Design tools name layers with ids (`<g id="Wheel_2">`) and make them unique with a
//! counter. A counter that only tells copies apart is noise to a grammar author, so
//! [`strip_counter_among`] removes Illustrator's copy suffix (`eye_1_`) and Figma's copy
//! numbers (`Vector_2` beside `Vector`), but keeps names whose number is all that tells
//! distinct layers apart (`Layer_1`, `Layer_2`). Which attributes are read is [`TagFrom`].

pub use gmotion::tagging::TagFrom;

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
}
