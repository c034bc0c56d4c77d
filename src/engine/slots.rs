//! Slots: which of a tag's paint properties the grammar's `slots` directive (`slots fill
//! stroke opacity`) opens to themes.
//!
//! The Lottie exporter gives each tag's solid fill colour, stroke colour or opacity the
//! slot id `TAG.fill`, `TAG.stroke`, `TAG.opacity` (the Lottie spec's `sid`, its value in the
//! document's `slots`), so that a page or a dotLottie theme recolours exactly the shapes of
//! that tag. The engine only carries the choice; the exporter writes it.

/// The kinds of property the `slots` directive names.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SlotKinds {
    /// Solid fill colours (`TAG.fill`).
    pub fill: bool,
    /// Solid stroke colours (`TAG.stroke`).
    pub stroke: bool,
    /// The shapes' opacity (`TAG.opacity`).
    pub opacity: bool,
}

impl SlotKinds {
    /// Whether any kind is asked for.
    pub fn any(self) -> bool {
        self.fill || self.stroke || self.opacity
    }

    /// These kinds with `word` (`fill`, `stroke` or `opacity`) added; `None` for another word.
    pub fn with(self, word: &str) -> Option<SlotKinds> {
        let mut k = self;
        match word {
            "fill" => k.fill = true,
            "stroke" => k.stroke = true,
            "opacity" => k.opacity = true,
            _ => return None,
        }
        Some(k)
    }
}
