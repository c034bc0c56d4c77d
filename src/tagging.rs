//! How an importer names shapes and chooses the animated units: the options that the
//! grammar's `tag_from` and `units` directives (and the command line's `--tag-from` and
//! `--units`) set. The importers implement them; the core only carries the choice.

/// Which source attribute names a shape's tag.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TagFrom {
    /// The nearest of `data-tag`, the first `class`, `inkscape:label` on the element or an
    /// ancestor; else the id of the nearest ancestor `<g>` without its counter; else the
    /// element's name.
    #[default]
    Auto,
    /// Only `data-tag`, then the element's name.
    DataTag,
    /// Only the first class name, then the element's name.
    Class,
    /// Only `inkscape:label`, then the element's name.
    Label,
    /// Only the id of the nearest `<g>` without its counter, then the element's name.
    Layer,
}

impl TagFrom {
    /// Whether this source reads the explicit tag attributes (`data-tag`, `class`, `label`).
    pub fn reads_attributes(self) -> bool {
        !matches!(self, TagFrom::Layer)
    }

    /// Whether this source reads layer (`<g>`) ids.
    pub fn reads_layers(self) -> bool {
        matches!(self, TagFrom::Auto | TagFrom::Layer)
    }
}

/// Which nodes become animated units (shapes). Units never nest: inside a unit nothing else
/// is one. Clip, mask and pattern content is never a unit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Units {
    /// A group (`<g>`, `<a>`, or a `use` of a group or symbol) that carries an explicit
    /// tag itself (`data-tag`, `class` or `inkscape:label`, as [`TagFrom`] selects) is one
    /// unit, so a character drawn with many paths moves as one piece; the outermost such
    /// group wins. An Inkscape layer's label names its paths but does not make the layer a
    /// unit, and neither does an Illustrator layer id. Each `<text>` is one unit. Every
    /// other visible path is its own unit.
    #[default]
    Auto,
    /// Every visible path (and every glyph run of a text) is a unit.
    Paths,
    /// Every outermost group that carries a tag itself, layer ids and Inkscape layer labels
    /// included, is a unit; visible paths outside such groups are units of their own.
    Groups,
}
