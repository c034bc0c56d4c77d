//! The bundled examples, inside the binary, so `gmotion demo` runs them wherever the binary
//! is (a copied or installed binary has no source tree beside it). `cli/tests/cli.rs` checks
//! that every example of `grammars/` is here.

/// What an example runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A grammar (`NAME.gm`) on its scene (`NAME.svg`).
    Grammar,
    /// Data-driven transitions (`NAME.targets.json`) on a scene (`NAME.svg`).
    Transitions,
}

/// One bundled example: its files, by name.
pub struct Example {
    /// Its name (`toy`, `histogram`).
    pub name: &'static str,
    /// What it runs.
    pub kind: Kind,
    /// What it shows: a line, or the grammar (whose opening comment says it).
    pub about: &'static str,
    /// Its files: (name, bytes); the scene first.
    pub files: &'static [(&'static str, &'static [u8])],
}

macro_rules! grammar {
    ($name:literal) => {
        Example {
            name: $name,
            kind: Kind::Grammar,
            about: include_str!(concat!("../../grammars/", $name, ".gm")),
            files: &[
                (
                    concat!($name, ".svg"),
                    include_bytes!(concat!("../../grammars/", $name, ".svg")),
                ),
                (
                    concat!($name, ".gm"),
                    include_bytes!(concat!("../../grammars/", $name, ".gm")),
                ),
            ],
        }
    };
}

macro_rules! transitions {
    ($name:literal, $about:literal) => {
        Example {
            name: $name,
            kind: Kind::Transitions,
            about: $about,
            files: &[
                (
                    concat!($name, ".svg"),
                    include_bytes!(concat!("../../grammars/", $name, ".svg")),
                ),
                (
                    concat!($name, ".targets.json"),
                    include_bytes!(concat!("../../grammars/", $name, ".targets.json")),
                ),
            ],
        }
    };
}

/// Every bundled example, by name.
pub const EXAMPLES: &[Example] = &[
    grammar!("abstract"),
    grammar!("checkmark"),
    grammar!("crack"),
    grammar!("cube"),
    grammar!("follow"),
    grammar!("growing_tangle"),
    grammar!("intersections"),
    grammar!("intersections_mini"),
    grammar!("kinetic"),
    grammar!("leaf"),
    grammar!("logo_morph"),
    grammar!("panel"),
    grammar!("priorities"),
    grammar!("regroup"),
    grammar!("statue"),
    grammar!("teaser"),
    grammar!("toy"),
    grammar!("variations"),
    transitions!(
        "histogram",
        "bins under a rapidly dragged selection, counts smoothed by a spring (Reach & North sec. 8.1)"
    ),
    transitions!(
        "permutation",
        "items travel elliptical arcs at constant speed (Reach & North sec. 8.2)"
    ),
    transitions!(
        "revisions",
        "a document's revision history: characters grow, move and shrink (Reach & North sec. 8.3)"
    ),
];

impl Example {
    /// The example called `name`.
    pub fn named(name: &str) -> Option<&'static Example> {
        EXAMPLES.iter().find(|e| e.name == name)
    }

    /// What it shows, in a line: the grammar's first comment line, or the description.
    pub fn summary(&self) -> String {
        match self.kind {
            Kind::Transitions => self.about.to_string(),
            Kind::Grammar => {
                // The opening comment, joined, cut at a word near 90 characters.
                let words: Vec<&str> = (self.about.lines())
                    .map_while(|l| l.strip_prefix('#'))
                    .flat_map(str::split_whitespace)
                    .collect();
                let mut text = String::new();
                for w in &words {
                    if text.len() + w.len() > 90 {
                        text.push('…');
                        return text;
                    }
                    if !text.is_empty() {
                        text.push(' ');
                    }
                    text.push_str(w);
                }
                text
            }
        }
    }
}
