//! The scenes of the gMotion gallery (Table 1 of the paper at its scale): `teaser`,
//! `crack`, `statue`, `intersections_mini` and `intersections`, plus the scenes of the
//! `variations` and `priorities` examples. The paper's supplemental art is not public, so
//! these are new drawings made to the paper's descriptions and shape counts; they are
//! generated because most of them are hundreds or thousands of regular pieces (shards, mosaic
//! tiles, street lattices) whose coordinates nobody should type.
//!
//! The two intersections examples share their rules, which are generated too (one block of
//! rules per kind of patch), so the files cannot drift apart: only the header differs.

use std::fmt::Write as _;

/// A generated gallery file: its name in `grammars/` and its text.
#[derive(Clone, Debug)]
pub struct GalleryFile {
    /// File name (`crack.svg`).
    pub name: String,
    /// The file's text.
    pub text: String,
}

/// Every generated gallery file, in a fixed order.
pub fn files() -> Vec<GalleryFile> {
    let f = |name: &str, text: String| GalleryFile {
        name: name.to_string(),
        text,
    };
    vec![
        f("teaser.svg", teaser()),
        f("crack.svg", crack()),
        f("statue.svg", statue()),
        f("intersections_mini.svg", intersections_scene(4, 4)),
        f(
            "intersections.svg",
            intersections_scene(INTERSECTIONS.0, INTERSECTIONS.1),
        ),
        f("intersections_mini.gm", intersections_grammar(true)),
        f("intersections.gm", intersections_grammar(false)),
        f("variations.svg", dancers("variations")),
        f("priorities.svg", dancers("priorities")),
    ]
}

/// Columns and rows of crossings in the large intersections scene: with the plazas that
/// every other cell holds, 8216 shapes: the nearest lattice to the paper's 8214
/// (see `intersections_scene`).
const INTERSECTIONS: (usize, usize) = (64, 40);

/// A deterministic hash in [0, 1) of two integers and a salt (SplitMix64's finaliser):
/// the jitter of the drawings, stable across platforms.
fn hash(a: i64, b: i64, salt: u64) -> f64 {
    let mut z = (a as u64)
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add((b as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F))
        .wrapping_add(salt.wrapping_mul(0x1656_67B1_9E37_79F9));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

/// An SVG document being written: the header, then one element per line.
struct Svg(String);

impl Svg {
    fn new(w: u32, h: u32, background: &str) -> Svg {
        let mut s = format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\">\n"
        );
        let _ = writeln!(
            s,
            "<rect data-tag=\"background\" width=\"{w}\" height=\"{h}\" fill=\"{background}\"/>"
        );
        Svg(s)
    }

    /// One element, `data-tag` first: `el("circle", "sun", "cx=\"1\" …")`.
    fn el(&mut self, kind: &str, tag: &str, attrs: &str) {
        let _ = writeln!(self.0, "<{kind} data-tag=\"{tag}\" {attrs}/>");
    }

    /// A closed polygon as a path, coordinates to 0.1.
    fn polygon(&mut self, tag: &str, pts: &[(f64, f64)], style: &str) {
        let mut d = String::new();
        for (i, (x, y)) in pts.iter().enumerate() {
            let _ = write!(d, "{}{:.1} {:.1}", if i == 0 { "M" } else { " L" }, x, y);
        }
        self.el("path", tag, &format!("d=\"{d} Z\" {style}"));
    }

    fn finish(mut self) -> String {
        self.0.push_str("</svg>\n");
        self.0
    }
}

/// An `#rrggbb` colour between two, `t` in [0, 1].
fn mix(a: u32, b: u32, t: f64) -> String {
    let ch = |c: u32, s: u32| ((c >> s) & 0xff) as f64;
    let m = |s| (ch(a, s) + (ch(b, s) - ch(a, s)) * t).round() as u32;
    format!("#{:02x}{:02x}{:02x}", m(16), m(8), m(0))
}

/// gMotion Fig. 1's kind of scene: a small town whose day turns to night and back, with a
/// car driving on a scrolling road. 209 shapes besides the background.
fn teaser() -> String {
    let mut s = Svg::new(640, 360, "#f7d9a8");
    s.el(
        "rect",
        "sky",
        "width=\"640\" height=\"300\" fill=\"#f6c28b\"",
    );
    for i in 0..50 {
        let (x, y) = (8.0 + 624.0 * hash(i, 1, 11), 6.0 + 190.0 * hash(i, 2, 11));
        let r = 1.0 + 1.2 * hash(i, 3, 11);
        s.el(
            "circle",
            "star",
            &format!("cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"{r:.1}\" fill=\"#fffbe6\""),
        );
    }
    // The moon is drawn where it shines at night; the grammar starts it below the hills.
    s.el(
        "circle",
        "moon",
        "cx=\"130\" cy=\"70\" r=\"22\" fill=\"#f4f1de\"",
    );
    for i in 0..12 {
        let a = (i as f64) * std::f64::consts::TAU / 12.0;
        let (c, si) = (a.cos(), a.sin());
        let (r0, r1, hw) = (46.0, 64.0, 4.0);
        let p = |r: f64, off: f64| (500.0 + r * c - off * si, 100.0 + r * si + off * c);
        s.polygon(
            "ray",
            &[p(r0, -hw), p(r1, 0.0), p(r0, hw)],
            "fill=\"#ffd166\"",
        );
    }
    s.el(
        "circle",
        "sun",
        "cx=\"500\" cy=\"100\" r=\"34\" fill=\"#ffb347\"",
    );
    for (k, (cx, cy)) in [(90.0, 120.0), (300.0, 60.0), (420.0, 170.0), (590.0, 40.0)]
        .into_iter()
        .enumerate()
    {
        for (dx, dy, rx, ry) in [
            (-22.0, 4.0, 20.0, 12.0),
            (0.0, -4.0, 24.0, 16.0),
            (24.0, 4.0, 18.0, 11.0),
        ] {
            let w = 1.0 + 0.15 * (k as f64 - 1.5);
            s.el(
                "ellipse",
                "cloud",
                &format!(
                    "cx=\"{:.1}\" cy=\"{:.1}\" rx=\"{:.1}\" ry=\"{:.1}\" fill=\"#fff7ee\"",
                    cx + dx * w,
                    cy + dy,
                    rx * w,
                    ry
                ),
            );
        }
    }
    for (i, (d, fill)) in [
        (
            "M0 250 Q120 170 260 240 T520 230 T640 220 V300 H0 Z",
            "#8db580",
        ),
        ("M0 270 Q160 215 330 262 T640 250 V300 H0 Z", "#6a994e"),
        ("M0 285 Q200 255 400 282 T640 276 V300 H0 Z", "#4f7942"),
    ]
    .into_iter()
    .enumerate()
    {
        let _ = i;
        s.el("path", "hill", &format!("d=\"{d}\" fill=\"{fill}\""));
    }
    // Eight buildings with a grid of windows each: 80 windows.
    let buildings = [
        (60.0, 150.0, 46.0, 3usize, 4usize),
        (116.0, 120.0, 54.0, 3, 4),
        (180.0, 170.0, 40.0, 2, 4),
        (230.0, 100.0, 50.0, 3, 5),
        (292.0, 160.0, 44.0, 2, 4),
        (346.0, 130.0, 52.0, 3, 3),
        (408.0, 180.0, 40.0, 2, 2),
        (458.0, 140.0, 50.0, 3, 4),
    ];
    let colours = [
        "#b8c0c8", "#a3b1c2", "#c9b79c", "#9aa5b1", "#c2b2a3", "#aab7b8", "#bfae9f", "#a0aec0",
    ];
    let mut windows = Vec::new();
    for (b, &(x, top, w, cols, rows)) in buildings.iter().enumerate() {
        s.el(
            "rect",
            "building",
            &format!(
                "x=\"{x}\" y=\"{top}\" width=\"{w}\" height=\"{}\" fill=\"{}\"",
                300.0 - top,
                colours[b]
            ),
        );
        let (gap_x, gap_y) = (w / cols as f64, 22.0);
        for r in 0..rows {
            for c in 0..cols {
                windows.push((
                    x + gap_x * c as f64 + gap_x / 2.0 - 5.0,
                    top + 12.0 + gap_y * r as f64,
                ));
            }
        }
    }
    for (x, y) in windows {
        s.el(
            "rect",
            "window",
            &format!("x=\"{x:.1}\" y=\"{y:.1}\" width=\"10\" height=\"12\" fill=\"#ffe08a\""),
        );
    }
    for (i, x) in [30.0, 170.0, 282.0, 398.0, 540.0, 610.0]
        .into_iter()
        .enumerate()
    {
        let h = 26.0 + 10.0 * hash(i as i64, 0, 3);
        s.el(
            "rect",
            "trunk",
            &format!(
                "x=\"{:.1}\" y=\"{:.1}\" width=\"6\" height=\"{h:.1}\" fill=\"#6b4f3a\"",
                x - 3.0,
                300.0 - h
            ),
        );
        s.el(
            "circle",
            "crown",
            &format!(
                "cx=\"{x}\" cy=\"{:.1}\" r=\"{:.1}\" fill=\"#3a7d44\"",
                300.0 - h - 10.0,
                15.0 + 4.0 * hash(i as i64, 1, 3)
            ),
        );
    }
    s.el(
        "rect",
        "road",
        "y=\"300\" width=\"640\" height=\"60\" fill=\"#3d405b\"",
    );
    // Dashes every 48 px from -48 to beyond the right edge: moved by one period they look
    // the same, so the road scrolls forever.
    for i in 0..16 {
        s.el(
            "rect",
            "dash",
            &format!(
                "x=\"{}\" y=\"327\" width=\"26\" height=\"5\" fill=\"#f2e9e4\"",
                -48 + 48 * i
            ),
        );
    }
    for (x, fill) in [(150.0, "#e63946"), (420.0, "#457b9d")] {
        s.el(
            "path",
            "car",
            &format!("d=\"M{x} 346 v-14 l14 -12 h40 l14 12 h14 v14 Z\" fill=\"{fill}\""),
        );
        for dx in [16.0, 62.0] {
            // A wheel with a hub mark, so its turning shows.
            s.el(
                "path",
                "wheel",
                &format!(
                    "d=\"M{0} 346 m-8 0 a8 8 0 1 0 16 0 a8 8 0 1 0 -16 0 Z M{0} 340 l2.5 6 h-5 Z\" fill=\"#22223b\" fill-rule=\"evenodd\"",
                    x + dx
                ),
            );
        }
    }
    for i in 0..6 {
        let (x, y) = (
            230.0 + 34.0 * i as f64,
            40.0 + 14.0 * hash(i, 0, 5) + 6.0 * (i % 2) as f64,
        );
        s.el(
            "path",
            "bird",
            &format!(
                "d=\"M{:.1} {y:.1} q6 -7 12 0 q6 -7 12 0\" fill=\"none\" stroke=\"#2b2d42\" stroke-width=\"2\" stroke-linecap=\"round\"",
                x - 12.0
            ),
        );
    }
    s.finish()
}

/// The crack's rings of shards: 9 rings of 40 shards about the impact point, radial
/// cracks and concentric ones jittered at shared vertices so the shards stay joined.
pub const CRACK_RINGS: usize = 9;
const CRACK_SECTORS: usize = 40;

/// A round pane of glass struck at its centre, in 360 connected shards tagged by ring
/// (`r0` innermost … `r8`): what the paper's crack animation needs, small units connected
/// in space whose motion follows cause and effect.
fn crack() -> String {
    let (cx, cy, radius) = (240.0, 240.0, 214.0);
    let mut s = Svg::new(480, 480, "#1f2a36");
    s.el(
        "circle",
        "frame",
        &format!(
            "cx=\"{cx}\" cy=\"{cy}\" r=\"{}\" fill=\"#4a5562\"",
            radius + 12.0
        ),
    );
    // Vertex (ring boundary i, radial crack j); boundary 0 is the impact point itself.
    let vertex = |i: usize, j: usize| -> (f64, f64) {
        if i == 0 {
            return (cx, cy);
        }
        let j = j % CRACK_SECTORS;
        let t = i as f64 / CRACK_RINGS as f64;
        let outer = i == CRACK_RINGS;
        let r = radius
            * t.powf(1.25)
            * if outer {
                1.0
            } else {
                1.0 + 0.16 * (hash(i as i64, j as i64, 7) - 0.5)
            };
        let a = (j as f64 + 0.7 * (hash(i as i64, j as i64, 8) - 0.5)) * std::f64::consts::TAU
            / CRACK_SECTORS as f64;
        (cx + r * a.cos(), cy + r * a.sin())
    };
    for ring in 0..CRACK_RINGS {
        for j in 0..CRACK_SECTORS {
            let mut pts = vec![vertex(ring + 1, j), vertex(ring + 1, j + 1)];
            if ring == 0 {
                pts.push(vertex(0, 0));
            } else {
                pts.push(vertex(ring, j + 1));
                pts.push(vertex(ring, j));
            }
            // Glass: pale blue, lighter towards the rim, each shard a little apart; the joins in
            // the glass's own colour, so the pane looks whole until the crack lights them.
            let t =
                ring as f64 / (CRACK_RINGS - 1) as f64 * 0.6 + 0.4 * hash(ring as i64, j as i64, 9);
            s.polygon(
                &format!("r{ring}"),
                &pts,
                &format!(
                    "fill=\"{}\" stroke=\"#a3d5e6\" stroke-width=\"0.8\" stroke-linejoin=\"round\"",
                    mix(0x8ecae6, 0xcdeef4, t)
                ),
            );
        }
    }
    s.finish()
}

/// A marble bust on a plinth in a mosaic of 960 tiles (30 × 32, 14 px), tagged by region:
/// `sky` (the background tiles, in two alternating sets `sky` and `air`), `laurel`, `hair`,
/// `face`, `eye`, `neck`, `drape` and `plinth`.
fn statue() -> String {
    let (cols, rows, cell) = (30i64, 32i64, 14.0);
    let mut s = Svg::new(
        (cols as f64 * cell) as u32,
        (rows as f64 * cell) as u32,
        "#f3efe6",
    );
    for r in 0..rows {
        for c in 0..cols {
            let (x, y) = ((c as f64 + 0.5) * cell, (r as f64 + 0.5) * cell);
            let head = ((x - 210.0) / 66.0).powi(2) + ((y - 150.0) / 82.0).powi(2);
            let drape = ((x - 210.0) / 165.0).powi(2) + ((y - 390.0) / 120.0).powi(2);
            let (tag, base, spread) = if y > 402.0 && (88.0..332.0).contains(&x) {
                ("plinth", 0x6d6875, 0.25)
            } else if head < 1.0 && (y < 112.0 || (head > 0.62 && y < 168.0 && x > 214.0)) {
                ("hair", 0xb5a48f, 0.3)
            } else if head < 1.0
                && (y - 138.0).abs() < 8.0
                && ((x - 182.0).abs() < 9.0 || (x - 238.0).abs() < 9.0)
            {
                ("eye", 0x8d99ae, 0.2)
            } else if head < 1.0 {
                ("face", 0xe8e0d2, 0.25)
            } else if (1.0..1.5).contains(&head) && y < 150.0 {
                ("laurel", 0x6a994e, 0.35)
            } else if (184.0..236.0).contains(&x) && (210.0..300.0).contains(&y) {
                ("neck", 0xdcd3c3, 0.2)
            } else if drape < 1.0 && y > 280.0 && y <= 402.0 {
                ("drape", 0xcfc6b6, 0.35)
            } else if (r + c) % 2 == 0 {
                ("sky", 0x9ec1cf, 0.3)
            } else {
                ("air", 0xb7d3df, 0.3)
            };
            let t = spread * hash(r, c, 21);
            s.el(
                "rect",
                tag,
                &format!(
                    "x=\"{:.0}\" y=\"{:.0}\" width=\"12\" height=\"12\" rx=\"2\" fill=\"{}\" stroke=\"#5c5346\" stroke-width=\"0.6\"",
                    c as f64 * cell + 1.0,
                    r as f64 * cell + 1.0,
                    mix(base, 0xffffff, t)
                ),
            );
        }
    }
    s.finish()
}

/// Spacing of the intersections lattice, in pixels, the same in both scenes so that one
/// grammar draws both.
const SPACING: f64 = 32.0;

/// Number of kinds of patch in the intersections scenes.
const KINDS: usize = 4;

/// The kind of the 2 × 2-cell patch at (pc, pr): in the mini scene (2 × 2 patches) each
/// kind once, and in the large one the same four repeating in a shuffled order.
fn patch_kind(pc: usize, pr: usize, mini: bool) -> usize {
    if mini {
        pc + 2 * pr
    } else {
        (pc + 2 * pr + (hash(pc as i64, pr as i64, 31) * 4.0) as usize) % KINDS
    }
}

/// A street lattice: `cols` × `rows` crossings (`node`), the street segments between them
/// (`hseg`, `vseg`) and a plaza (`block`) in every cell whose column and row are both even;
/// each shape's tag ends in the kind of its 2 × 2-cell patch (`node2`, `hseg0`, …).
/// 4 × 4 gives the paper's 44 shapes, 64 × 40 8216 (the paper's large scene has 8214).
/// Tags are classes and paint comes from a style sheet, so the 8216 shapes take 37 bytes
/// each on average.
fn intersections_scene(cols: usize, rows: usize) -> String {
    let mini = cols == 4;
    let margin = 24.0;
    let w = (margin * 2.0 + SPACING * (cols - 1) as f64) as u32;
    let h = (margin * 2.0 + SPACING * (rows - 1) as f64) as u32;
    let mut s = Svg::new(w, h, "#fbf7f0");
    let street = ["#e07a5f", "#3d405b", "#81b29a", "#f2cc8f"];
    let plaza = ["#f4a261", "#6d597a", "#2a9d8f", "#e9c46a"];
    s.0.push_str("<style>");
    for k in 0..KINDS {
        let _ = write!(
            s.0,
            ".hseg{k},.vseg{k}{{fill:{}}}.block{k}{{fill:{}}}.node{k}{{fill:#264653}}",
            street[k], plaza[k]
        );
    }
    s.0.push_str("</style>\n");
    let at = |c: usize, r: usize| (margin + SPACING * c as f64, margin + SPACING * r as f64);
    // The kind of a cell (c, r), clamped so the last row and column join their patch.
    let kind = |c: usize, r: usize| patch_kind(c.min(cols - 2) / 2, r.min(rows - 2) / 2, mini);
    for r in (0..rows - 1).step_by(2) {
        for c in (0..cols - 1).step_by(2) {
            let (x, y) = at(c, r);
            let _ = writeln!(
                s.0,
                "<path class=\"block{}\" d=\"M{} {}h20v20h-20z\"/>",
                kind(c, r),
                x + 6.0,
                y + 6.0
            );
        }
    }
    for r in 0..rows {
        for c in 0..cols {
            let (x, y) = at(c, r);
            let k = kind(c, r);
            if c + 1 < cols {
                let _ = writeln!(
                    s.0,
                    "<path class=\"hseg{k}\" d=\"M{} {}h22v4h-22z\"/>",
                    x + 5.0,
                    y - 2.0
                );
            }
            if r + 1 < rows {
                let _ = writeln!(
                    s.0,
                    "<path class=\"vseg{k}\" d=\"M{} {}h4v22h-4z\"/>",
                    x - 2.0,
                    y + 5.0
                );
            }
        }
    }
    for r in 0..rows {
        for c in 0..cols {
            let (x, y) = at(c, r);
            let _ = writeln!(
                s.0,
                "<circle class=\"node{}\" cx=\"{x}\" cy=\"{y}\" r=\"4\"/>",
                kind(c, r)
            );
        }
    }
    s.finish()
}

/// The rules of both intersections examples: a shared structure, then one block of
/// episodes for each of the four kinds of patch, each kind with its own motions for its
/// crossings, streets and plazas. Every episode is placed in time by the patch it belongs
/// to (`noise` of the patch's cell), so the large scene shows patches going off at their
/// own moments.
fn intersections_grammar(mini: bool) -> String {
    let mut g = String::new();
    if mini {
        g.push_str(
            "# gMotion Fig. 11 (top), \"intersections mini\": a grammar designed on 44 shapes, a\n\
             # 4 x 4 street lattice in four patches, one of each kind. intersections.gm runs the\n\
             # same rules on 8216 shapes (`cargo xtask gallery` writes both from one source).\n\
             scene intersections_mini.svg\nduration 4s\n",
        );
    } else {
        g.push_str(
            "# gMotion Fig. 11 (bottom), \"intersections\": the rules of intersections_mini.gm,\n\
             # unchanged, on a 64 x 40 street lattice of 8216 shapes in 640 patches of the same\n\
             # four kinds (`cargo xtask gallery` writes both from one source).\n\
             scene intersections.svg\nduration 8s\n",
        );
    }
    g.push_str("fps 30\n\n");
    g.push_str(
        "# Every timeline: an episode, a rest in which the whole lattice breathes, and the\n\
         # episode undone. When a patch's episode plays is the patch's own: noise at its\n\
         # 64 px cell, the same for every shape of the patch.\n",
    );
    let all: Vec<String> = (0..KINDS)
        .flat_map(|k| ["node", "hseg", "vseg", "block"].map(|r| format!("{r}{k}")))
        .collect();
    let _ = writeln!(
        g,
        "timesplit(0.4, 0.2, 0.4) : [all, ({})] -> [ep, rest, inv_ep]",
        all.join(", ")
    );
    g.push_str("timesplit(0.5, 0.5) : [rest, all] -> [breathe, inv_breathe]\n");
    g.push_str(
        "animate(affine, local, 0, scale(0.85), ease=ease-in-out) : [breathe, all] -> [held]\n",
    );
    g.push_str("animate(opacity, local, 0, 0.85) : [held, all] -> [dimmed]\n");
    // The episode's delay within its beat, by patch (64 px cells of the lattice).
    let when = "0.45 * d * (0.5 + 0.5 * noise(floor(cx / 64) * 0.9, floor(cy / 64) * 0.9))";
    // Per kind and role (crossing, horizontal street, vertical street, plaza): the motions
    // of the episode's first beat, then of its second.
    type Beats = [&'static [&'static str]; 2];
    let kinds: [[Beats; 4]; KINDS] = [
        // 0: the plaza turns and glows; streets fold into their crossings; crossings pulse.
        [
            [
                &[
                    "animate(affine, local, {w}, scale(2), ease=ease-out)",
                    "animate(fill, local, {w}, #e07a5f)",
                ],
                &[
                    "animate(border, local, {w}, #264653)",
                    "animate(stroke-width, local, {w}, 1.5)",
                    "animate(affine, local, {w}, scale(0.7))",
                ],
            ],
            [
                &[
                    "animate(affine, local, {w}, scale(0.2, 1), ease=ease-in-out)",
                    "animate(fill, local, {w}, #264653)",
                ],
                &[
                    "animate(opacity, local, {w}, 0.5)",
                    "animate(affine, world, {w}, translate(0, 3))",
                    "animate(fill, local, {w}, #e07a5f)",
                ],
            ],
            [
                &[
                    "animate(affine, local, {w}, scale(1, 0.2), ease=ease-in-out)",
                    "animate(fill, local, {w}, #264653)",
                ],
                &[
                    "animate(opacity, local, {w}, 0.5)",
                    "animate(affine, world, {w}, translate(3, 0))",
                    "animate(fill, local, {w}, #e07a5f)",
                ],
            ],
            [
                &[
                    "animate(affine, local, {w}, rotate(90) scale(1.3), ease=ease-in-out)",
                    "animate(fill, local, {w}, #ffd166)",
                ],
                &[
                    "animate(border, local, {w}, #e07a5f)",
                    "animate(stroke-width, local, {w}, 3)",
                    "animate(opacity, local, {w}, 0.9)",
                    "animate(affine, local, {w}, rotate(45))",
                ],
            ],
        ],
        // 1: a crossing-wide spin: streets swing about their middles, the plaza shrinks.
        [
            [
                &[
                    "animate(affine, local, {w}, scale(0.5))",
                    "animate(fill, local, {w}, #6d597a)",
                ],
                &[
                    "animate(opacity, local, {w}, 0.6)",
                    "animate(affine, world, {w}, translate(0, -4))",
                    "animate(affine, local, {w}, scale(1.6))",
                ],
            ],
            [
                &[
                    "animate(affine, local, {w}, rotate(90), ease=ease-in-out)",
                    "animate(fill, local, {w}, #b56576)",
                ],
                &[
                    "animate(affine, local, {w}, scale(0.8))",
                    "animate(opacity, local, {w}, 0.8)",
                    "animate(affine, local, {w}, rotate(45))",
                ],
            ],
            [
                &[
                    "animate(affine, local, {w}, rotate(-90), ease=ease-in-out)",
                    "animate(fill, local, {w}, #b56576)",
                ],
                &[
                    "animate(affine, local, {w}, scale(0.8))",
                    "animate(opacity, local, {w}, 0.8)",
                    "animate(affine, local, {w}, rotate(-45))",
                ],
            ],
            [
                &[
                    "animate(affine, local, {w}, scale(0.35), ease=ease-in)",
                    "animate(fill, local, {w}, #355070)",
                ],
                &[
                    "animate(affine, local, {w}, rotate(-45))",
                    "animate(border, local, {w}, #eaac8b)",
                    "animate(stroke-width, local, {w}, 4)",
                    "animate(affine, local, {w}, scale(2))",
                ],
            ],
        ],
        // 2: traffic: streets slide along themselves, crossings blink, the plaza lifts.
        [
            [
                &[
                    "animate(fill, local, {w}, #2a9d8f)",
                    "animate(affine, local, {w}, scale(1.6))",
                ],
                &[
                    "animate(border, local, {w}, #e9f5db)",
                    "animate(stroke-width, local, {w}, 2)",
                    "animate(fill, local, {w}, #264653)",
                ],
            ],
            [
                &[
                    "animate(affine, world, {w}, translate(10, 0), ease=ease-in-out)",
                    "animate(affine, local, {w}, scale(0.6, 1.5))",
                ],
                &[
                    "animate(fill, local, {w}, #264653)",
                    "animate(opacity, local, {w}, 0.7)",
                    "animate(affine, world, {w}, translate(-10, 0), ease=ease-in-out)",
                ],
            ],
            [
                &[
                    "animate(affine, world, {w}, translate(0, 10), ease=ease-in-out)",
                    "animate(affine, local, {w}, scale(1.5, 0.6))",
                ],
                &[
                    "animate(fill, local, {w}, #264653)",
                    "animate(opacity, local, {w}, 0.7)",
                    "animate(affine, world, {w}, translate(0, -10), ease=ease-in-out)",
                ],
            ],
            [
                &[
                    "animate(affine, world, {w}, translate(-4, -4), ease=ease-out)",
                    "animate(affine, local, {w}, skew(15, 0))",
                ],
                &[
                    "animate(fill, local, {w}, #e9f5db)",
                    "animate(border, local, {w}, #2a9d8f)",
                    "animate(stroke-width, local, {w}, 2.5)",
                    "animate(affine, local, {w}, skew(-30, 0))",
                ],
            ],
        ],
        // 3: the patch sways: skews, a plaza that flips over, streets that fade.
        [
            [
                &[
                    "animate(affine, local, {w}, scale(1.4, 0.6))",
                    "animate(fill, local, {w}, #f2cc8f)",
                ],
                &[
                    "animate(border, local, {w}, #3d405b)",
                    "animate(stroke-width, local, {w}, 1)",
                    "animate(affine, local, {w}, scale(0.6, 1.4))",
                ],
            ],
            [
                &[
                    "animate(affine, local, {w}, skew(0, 20), ease=ease-in-out)",
                    "animate(opacity, local, {w}, 0.25)",
                ],
                &[
                    "animate(fill, local, {w}, #e07a5f)",
                    "animate(affine, local, {w}, scale(1.2, 1))",
                    "animate(opacity, local, {w}, 1)",
                ],
            ],
            [
                &[
                    "animate(affine, local, {w}, skew(20, 0), ease=ease-in-out)",
                    "animate(opacity, local, {w}, 0.25)",
                ],
                &[
                    "animate(fill, local, {w}, #e07a5f)",
                    "animate(affine, local, {w}, scale(1, 1.2))",
                    "animate(opacity, local, {w}, 1)",
                ],
            ],
            [
                &[
                    "animate(affine, local, {w}, scale(-1, 1), ease=ease-in-out)",
                    "animate(fill, local, {w}, #3d405b)",
                    "animate(opacity, local, {w}, 0.8)",
                ],
                &[
                    "animate(affine, local, {w}, rotate(30))",
                    "animate(border, local, {w}, #f2cc8f)",
                    "animate(stroke-width, local, {w}, 3)",
                    "animate(fill, local, {w}, #f4a261)",
                ],
            ],
        ],
    ];
    for (k, roles) in kinds.iter().enumerate() {
        let _ = writeln!(g, "\n# Patches of kind {k}: crossings, streets, plaza.");
        for (role, beats) in ["node", "hseg", "vseg", "block"].iter().zip(roles) {
            let tag = format!("{role}{k}");
            let _ = writeln!(
                g,
                "timesplit(0.55, 0.45) : [ep, {tag}] -> [{tag}_a, {tag}_b]"
            );
            for (beat, motions) in ["a", "b"].iter().zip(beats) {
                // Each motion renames its slice, so the next one of the beat matches the new
                // name (`node0_a` → `node0_a1` → `node0_a2`) and they play together.
                for (i, m) in motions.iter().enumerate() {
                    let input = if i == 0 {
                        format!("{tag}_{beat}")
                    } else {
                        format!("{tag}_{beat}{i}")
                    };
                    let rule = m.replace("{w}", when);
                    let _ = writeln!(g, "{rule} : [{input}, {tag}] -> [{tag}_{beat}{}]", i + 1);
                }
            }
        }
    }
    g
}

/// A troupe of 24 shapes in three rows (`disc`, `square`, `tri`) with a highlighted trio in
/// the middle (`lead`), for the stochastic examples: the same art, two grammars.
fn dancers(which: &str) -> String {
    let mut s = Svg::new(480, 300, "#fdfbf7");
    let palette = ["#e4572e", "#17bebb", "#ffc914", "#2e282a", "#76b041"];
    for r in 0..3 {
        for c in 0..8 {
            let (x, y) = (60.0 + 52.0 * c as f64, 70.0 + 80.0 * r as f64);
            let lead = which == "priorities" && (3..5).contains(&c);
            let fill = if lead {
                "#7b2cbf"
            } else {
                palette[(c + r) % palette.len()]
            };
            let tag = if lead {
                "lead"
            } else {
                ["disc", "square", "tri"][r]
            };
            match r {
                0 => s.el(
                    "circle",
                    tag,
                    &format!("cx=\"{x}\" cy=\"{y}\" r=\"18\" fill=\"{fill}\""),
                ),
                1 => s.el(
                    "rect",
                    tag,
                    &format!(
                        "x=\"{}\" y=\"{}\" width=\"34\" height=\"34\" rx=\"4\" fill=\"{fill}\"",
                        x - 17.0,
                        y - 17.0
                    ),
                ),
                _ => s.polygon(
                    tag,
                    &[(x, y - 20.0), (x + 19.0, y + 14.0), (x - 19.0, y + 14.0)],
                    &format!("fill=\"{fill}\""),
                ),
            }
        }
    }
    s.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The committed gallery files are what the generator makes (`cargo xtask gallery`).
    #[test]
    fn committed_gallery_is_regenerated_exactly() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../grammars");
        for f in files() {
            let on_disk = std::fs::read_to_string(dir.join(&f.name)).unwrap_or_default();
            assert!(
                on_disk == f.text,
                "grammars/{} differs from its generator",
                f.name
            );
        }
    }
}
