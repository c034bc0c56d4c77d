//! The scene model: the SVG's structure kept as a tree (groups with transform, opacity, clip
//! path and mask; paths with fills and strokes; gradients and patterns), plus the list of
//! animated units ("shapes") that the grammars act on.
//!
//! Importers build a [`Scene`]; the engine never sees a file format. Every coordinate here
//! is in user units after usvg's normalisation: gradients and patterns are in user space,
//! `viewBox` is folded into the root group's transform.

use std::collections::HashMap;
use std::sync::Arc;

use base64::Engine as _;
use kurbo::{Affine, BezPath, Point, Rect, Shape as _};

use crate::color::Color;
use crate::measure::measure;

/// A whole picture: its canvas size, the node tree and the animated shapes.
#[derive(Clone, Debug)]
pub struct Scene {
    /// Canvas width in user units (the SVG's `width`).
    pub width: f64,
    /// Canvas height in user units.
    pub height: f64,
    /// The node tree; its transform holds the `viewBox` mapping.
    pub root: Group,
    /// The animated units in document order; `Node::unit` indexes into this list.
    pub shapes: Vec<Shape>,
    /// The scene's own time, when it moves by itself (a Lottie composition's).
    pub time: Option<SceneTime>,
    /// Shapes kept out of the drawing and read for their outlines only (morph targets: an
    /// SVG element with `display="none"`, or a path in `<defs>`), in document order.
    pub keys: Vec<KeyShape>,
}

/// A shape that is not drawn but whose outline a grammar may name (`shape(TAG[, ID])` as
/// the target of a morph): a key shape the designer drew and hid.
#[derive(Clone, Debug)]
pub struct KeyShape {
    /// Its tag, found as a drawn shape's would be.
    pub tag: String,
    /// Other tags it answers to (its element's id and its groups', as grammar names).
    pub aliases: Vec<String>,
    /// Its paths in canvas coordinates, in document order.
    pub paths: Vec<BezPath>,
}

impl KeyShape {
    /// Every tag the key shape answers to: its tag, then its aliases.
    pub fn tags(&self) -> impl Iterator<Item = &str> + Clone {
        std::iter::once(self.tag.as_str()).chain(self.aliases.iter().map(String::as_str))
    }
}

/// A scene's own timeline: a Lottie composition's length and frame rate. A grammar that
/// sets no `duration` runs for as long, and one that sets no `fps` at that rate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneTime {
    /// Length in seconds.
    pub duration: f64,
    /// Frames per second.
    pub fps: f64,
}

/// An animated unit: a leaf path, or a whole group that carries a tag.
#[derive(Clone, Debug)]
pub struct Shape {
    /// The tag rules select on (never empty; `all` matches every shape anyway). Its `id`
    /// counts within it, and `n` in expressions is the number of shapes that have it.
    pub tag: String,
    /// Other tags the shape answers to, rules selecting on any of them taking it: for an
    /// imported shape, the ids of its element and of the groups around it (as grammar
    /// names), and the tags a tag map (`--tags`) gives it. Never holds `tag` itself.
    pub aliases: Vec<String>,
    /// How many of the last [`aliases`](Shape::aliases) name ancestors that already move
    /// the shape through parenting (a Lottie scene's parent layers and the nulls of its
    /// rigs). A rule that takes the shape only through them gives it no motion of its own
    /// (it follows them, once), but still changes its paint and opacity.
    pub inherited: usize,
    /// A rig rather than a drawing: a Lottie null layer that moves the layers parented to
    /// it. It draws nothing and takes only motion, about its anchor point (its
    /// [`centroid`](Shape::centroid)); `all` does not take it, and `n`, `k` and `count`
    /// count drawings only.
    pub rig: bool,
    /// Unique within the tag, in document order, from 0.
    pub id: usize,
    /// The group grammar's group id (0 for imported shapes).
    pub group: usize,
    /// Paint order position among all shapes (0 = drawn first).
    pub z: usize,
    /// Child indices from the root to the unit's node.
    pub node_path: Vec<usize>,
    /// Transform from the unit node's parent coordinates to the canvas.
    pub parent_transform: Affine,
    /// Centroid (area centroid of the filled geometry) in canvas coordinates.
    pub centroid: Point,
    /// Bounding box of the geometry in canvas coordinates.
    pub bbox: Rect,
    /// The unit's representative fill colour (first solid fill; black if none).
    pub fill: Color,
    /// The unit's representative stroke colour (first solid stroke; black if none).
    pub stroke: Color,
    /// The unit's representative stroke width (first stroke's; 1 if none).
    pub stroke_width: f64,
    /// Its text: the layout of a unit that came from text, a piece's line and word.
    pub text: crate::text::TextPlace,
}

impl Shape {
    /// Every tag the shape answers to: its [`Shape::tag`], then its [`Shape::aliases`].
    pub fn tags(&self) -> impl Iterator<Item = &str> + Clone {
        std::iter::once(self.tag.as_str()).chain(self.aliases.iter().map(String::as_str))
    }

    /// The tags the shape answers to by itself: [`Shape::tags`] without the
    /// [`inherited`](Shape::inherited) names of the ancestors that move it.
    pub fn own_tags(&self) -> impl Iterator<Item = &str> + Clone {
        let own = self.aliases.len().saturating_sub(self.inherited);
        std::iter::once(self.tag.as_str()).chain(self.aliases[..own].iter().map(String::as_str))
    }
}

/// A node of the tree.
#[derive(Clone, Debug)]
pub enum Node {
    /// A group of nodes.
    Group(Group),
    /// A painted path.
    Path(PathNode),
    /// A raster image.
    Image(ImageNode),
}

impl Node {
    /// The node's id (may be empty).
    pub fn id(&self) -> &str {
        match self {
            Node::Group(g) => &g.id,
            Node::Path(p) => &p.id,
            Node::Image(i) => &i.id,
        }
    }

    /// The index of the animated unit this node is, if it is one.
    pub fn unit(&self) -> Option<usize> {
        match self {
            Node::Group(g) => g.unit,
            Node::Path(p) => p.unit,
            Node::Image(i) => i.unit,
        }
    }

    /// Makes the node animated unit `unit` (or no unit).
    pub fn set_unit(&mut self, unit: Option<usize>) {
        match self {
            Node::Group(g) => g.unit = unit,
            Node::Path(p) => p.unit = unit,
            Node::Image(i) => i.unit = unit,
        }
    }
}

/// A group: its children drawn into a layer with a transform, opacity, clip path and mask.
#[derive(Clone, Debug, Default)]
pub struct Group {
    /// Element id (may be empty).
    pub id: String,
    /// The name the designer gave the group besides its id (an Inkscape label, an
    /// Illustrator `data-name`; may be empty): shown to people (the studio's layer tree),
    /// never a name rules select by.
    pub label: String,
    /// Transform relative to the parent.
    pub transform: Affine,
    /// Group opacity in `0..=1`.
    pub opacity: f32,
    /// Clip path applied to the group.
    pub clip_path: Option<Arc<ClipPath>>,
    /// Mask applied to the group.
    pub mask: Option<Arc<Mask>>,
    /// Filter effects applied to the group's content (before clip, mask and opacity, as
    /// SVG applies them).
    pub filter: Option<Arc<Filter>>,
    /// Children in paint order.
    pub children: Vec<Node>,
    /// Set when this group is an animated unit.
    pub unit: Option<usize>,
}

impl Group {
    /// An empty, opaque group with an identity transform.
    pub fn new() -> Group {
        Group {
            opacity: 1.0,
            ..Group::default()
        }
    }

    /// The region this group's filter draws in, in the group's coordinates (`abs` maps
    /// them to the canvas): the source's, unless animated content may move out of it (a
    /// unit inside, or the group being a unit itself, whose outlines a per-vertex motion
    /// moves within the group), when it grows to cover the canvas plus the effects' reach
    /// (anything beyond is not seen). A region exported tight around a still shape (as
    /// Figma writes them) would otherwise cut off the shape it moves. `None` without a
    /// filter.
    pub fn filter_region(&self, abs: Affine, canvas: Rect) -> Option<Rect> {
        fn has_unit(g: &Group) -> bool {
            g.children
                .iter()
                .any(|n| n.unit().is_some() || matches!(n, Node::Group(h) if has_unit(h)))
        }
        let f = self.filter.as_ref()?;
        let moves = self.unit.is_some() || has_unit(self);
        if !moves || abs.determinant() == 0.0 {
            return Some(f.region);
        }
        let reach: f64 = f.effects.iter().map(Effect::reach).sum();
        let seen = abs.inverse().transform_rect_bbox(canvas);
        let scale = abs.determinant().abs().sqrt();
        Some(f.region.union(seen.inflate(reach / scale, reach / scale)))
    }

    /// The node at `path` (child indices from this group down, as [`Shape::node_path`]
    /// holds them), or `None` when the path leaves the tree.
    pub fn node_at(&self, path: &[usize]) -> Option<&Node> {
        let (last, parents) = path.split_last()?;
        let parent = parents
            .iter()
            .try_fold(self, |g, &i| match g.children.get(i)? {
                Node::Group(c) => Some(c),
                Node::Path(_) | Node::Image(_) => None,
            })?;
        parent.children.get(*last)
    }

    /// [`Group::node_at`], mutable.
    pub fn node_at_mut(&mut self, path: &[usize]) -> Option<&mut Node> {
        match (path, self.children.get_mut(*path.first()?)?) {
            ([_], node) => Some(node),
            ([_, rest @ ..], Node::Group(g)) => g.node_at_mut(rest),
            _ => None,
        }
    }
}

/// A path with its paint.
#[derive(Clone, Debug)]
pub struct PathNode {
    /// Element id (may be empty).
    pub id: String,
    /// Geometry in the parent group's coordinates.
    pub path: BezPath,
    /// Fill, if any.
    pub fill: Option<Fill>,
    /// Stroke, if any.
    pub stroke: Option<Stroke>,
    /// Whether the stroke is painted before the fill.
    pub stroke_first: bool,
    /// Set when this path is an animated unit.
    pub unit: Option<usize>,
}

/// A raster image, drawn with its top-left corner at the origin of its parent group's
/// coordinates and `width` × `height` units large (placement, `viewBox` fitting and
/// `preserveAspectRatio` are folded into the groups around it, as usvg does).
#[derive(Clone, Debug)]
pub struct ImageNode {
    /// Element id (may be empty).
    pub id: String,
    /// The encoded file, kept as it came so exporters can embed it unchanged.
    pub data: Arc<[u8]>,
    /// How `data` is encoded.
    pub format: ImageFormat,
    /// Width in the parent group's units (the image's pixel width).
    pub width: f64,
    /// Height in the parent group's units.
    pub height: f64,
    /// Whether the image is scaled smoothly (`false` for `image-rendering: pixelated`).
    pub smooth: bool,
    /// Set when this image is an animated unit.
    pub unit: Option<usize>,
}

impl ImageNode {
    /// The rectangle the image covers, in the parent group's coordinates.
    pub fn rect(&self) -> Rect {
        Rect::new(0.0, 0.0, self.width, self.height)
    }

    /// The pixel size the encoded image declares in its header (`None` when the header
    /// cannot be read). Players and renderers allocate this many pixels to decode it, so a
    /// few bytes can ask for gigabytes: importers check it against
    /// [`DEFAULT_MAX_IMAGE_PIXELS`] or the user's limit before keeping an image.
    pub fn pixel_size(&self) -> Option<(u64, u64)> {
        image_pixel_size(&self.data)
    }

    /// The image as a `data:` URL, as SVG `href`s and Lottie image assets embed it.
    pub fn data_url(&self) -> String {
        format!(
            "data:{};base64,{}",
            self.format.mime(),
            base64::engine::general_purpose::STANDARD.encode(&self.data)
        )
    }
}

/// The default largest raster image an importer keeps, in pixels once decoded: 2²⁶
/// (8192 × 8192, 256 MiB of RGBA), the same as the largest rendered image.
pub const DEFAULT_MAX_IMAGE_PIXELS: u64 = 1 << 26;

/// The pixel size an encoded PNG, JPEG, GIF or WebP image declares in its header.
pub fn image_pixel_size(data: &[u8]) -> Option<(u64, u64)> {
    let size = imagesize::blob_size(data).ok()?;
    Some((size.width as u64, size.height as u64))
}

/// The encodings of raster images.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    /// PNG.
    Png,
    /// JPEG.
    Jpeg,
    /// GIF (its first frame is drawn).
    Gif,
    /// WebP.
    Webp,
}

impl ImageFormat {
    /// The encoding of `data`, from its signature (`None` for anything else).
    pub fn sniff(data: &[u8]) -> Option<ImageFormat> {
        match data {
            [0x89, b'P', b'N', b'G', ..] => Some(ImageFormat::Png),
            [0xff, 0xd8, 0xff, ..] => Some(ImageFormat::Jpeg),
            [b'G', b'I', b'F', b'8', ..] => Some(ImageFormat::Gif),
            [
                b'R',
                b'I',
                b'F',
                b'F',
                _,
                _,
                _,
                _,
                b'W',
                b'E',
                b'B',
                b'P',
                ..,
            ] => Some(ImageFormat::Webp),
            _ => None,
        }
    }

    /// The MIME type.
    pub fn mime(self) -> &'static str {
        match self {
            ImageFormat::Png => "image/png",
            ImageFormat::Jpeg => "image/jpeg",
            ImageFormat::Gif => "image/gif",
            ImageFormat::Webp => "image/webp",
        }
    }
}

/// Fill rule.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FillRule {
    /// `nonzero`.
    #[default]
    NonZero,
    /// `evenodd`.
    EvenOdd,
}

/// How a path's interior is painted.
#[derive(Clone, Debug)]
pub struct Fill {
    /// What is painted.
    pub paint: Paint,
    /// Fill opacity in `0..=1`.
    pub opacity: f32,
    /// Fill rule.
    pub rule: FillRule,
}

/// Line cap.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LineCap {
    /// `butt`.
    #[default]
    Butt,
    /// `round`.
    Round,
    /// `square`.
    Square,
}

/// Line join.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LineJoin {
    /// `miter`.
    #[default]
    Miter,
    /// `miter-clip`.
    MiterClip,
    /// `round`.
    Round,
    /// `bevel`.
    Bevel,
}

/// How a path's outline is painted.
#[derive(Clone, Debug)]
pub struct Stroke {
    /// What is painted.
    pub paint: Paint,
    /// Stroke opacity in `0..=1`.
    pub opacity: f32,
    /// Line width in user units.
    pub width: f64,
    /// Line cap.
    pub cap: LineCap,
    /// Line join.
    pub join: LineJoin,
    /// Miter limit.
    pub miter_limit: f64,
    /// Dash lengths (an even count), if dashed.
    pub dash: Option<Vec<f64>>,
    /// Dash offset.
    pub dash_offset: f64,
}

/// A paint server.
#[derive(Clone, Debug)]
pub enum Paint {
    /// A solid colour (its alpha is 1; opacity lives on the fill or stroke).
    Solid(Color),
    /// A linear gradient.
    Linear(Arc<LinearGradient>),
    /// A radial gradient.
    Radial(Arc<RadialGradient>),
    /// A pattern tile.
    Pattern(Arc<Pattern>),
}

impl Paint {
    /// A gradient's stops; `None` for a solid colour or a pattern.
    pub fn gradient_stops(&self) -> Option<&[Stop]> {
        match self {
            Paint::Linear(g) => Some(&g.stops),
            Paint::Radial(g) => Some(&g.stops),
            Paint::Solid(_) | Paint::Pattern(_) => None,
        }
    }
}

/// What a gradient does outside its `0..1` range.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Spread {
    /// Extend the end colours.
    #[default]
    Pad,
    /// Mirror.
    Reflect,
    /// Repeat.
    Repeat,
}

/// A gradient stop; `color.a` holds the stop opacity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stop {
    /// Position in `0..=1`.
    pub offset: f32,
    /// Colour with the stop opacity as alpha.
    pub color: Color,
}

/// A linear gradient in user space.
#[derive(Clone, Debug)]
pub struct LinearGradient {
    /// Element id.
    pub id: String,
    /// Start point.
    pub start: Point,
    /// End point.
    pub end: Point,
    /// Gradient transform.
    pub transform: Affine,
    /// Spread method.
    pub spread: Spread,
    /// Stops, sorted by offset.
    pub stops: Vec<Stop>,
}

/// A radial gradient in user space.
#[derive(Clone, Debug)]
pub struct RadialGradient {
    /// Element id.
    pub id: String,
    /// Centre of the end circle.
    pub center: Point,
    /// Radius of the end circle.
    pub radius: f64,
    /// Centre of the focal (start) circle.
    pub focal: Point,
    /// Radius of the focal circle.
    pub focal_radius: f64,
    /// Gradient transform.
    pub transform: Affine,
    /// Spread method.
    pub spread: Spread,
    /// Stops, sorted by offset.
    pub stops: Vec<Stop>,
}

/// A pattern tile in user space.
#[derive(Clone, Debug)]
pub struct Pattern {
    /// Element id.
    pub id: String,
    /// The tile rectangle.
    pub rect: Rect,
    /// Pattern transform.
    pub transform: Affine,
    /// The tile's content.
    pub root: Group,
}

/// The filter effects on a group: the ones every output can carry (SVG as filter
/// primitives, Lottie as After Effects effects). Importers rasterise any other filter.
#[derive(Clone, Debug, PartialEq)]
pub struct Filter {
    /// Element id (may be empty).
    pub id: String,
    /// The region the effects draw in, in the group's coordinates (content outside it is
    /// cut off, as SVG's filter region does).
    pub region: Rect,
    /// The effects, each applied to the result of the one before.
    pub effects: Vec<Effect>,
    /// Whether blurs mix colours in linear RGB (SVG's default) rather than sRGB.
    pub linear_rgb: bool,
}

/// One filter effect, in the filtered group's coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Effect {
    /// A Gaussian blur with standard deviations `x` and `y`.
    Blur(kurbo::Vec2),
    /// The content's silhouette, moved by `offset`, blurred by `std_dev`, in `color`,
    /// drawn under the content.
    DropShadow {
        /// How far the shadow falls.
        offset: kurbo::Vec2,
        /// Standard deviations of its blur.
        std_dev: kurbo::Vec2,
        /// Its colour, alpha included.
        color: Color,
    },
}

impl Effect {
    /// How far the effect draws beyond its input's edges (three standard deviations,
    /// where a Gaussian has all but 0.3 % of its weight, plus the shadow's offset).
    pub fn reach(&self) -> f64 {
        match *self {
            Effect::Blur(s) => 3.0 * s.x.max(s.y),
            Effect::DropShadow {
                offset, std_dev, ..
            } => 3.0 * std_dev.x.max(std_dev.y) + offset.hypot(),
        }
    }
}

/// A clip path.
#[derive(Clone, Debug)]
pub struct ClipPath {
    /// Element id.
    pub id: String,
    /// Transform applied to the clip content.
    pub transform: Affine,
    /// A clip path applied to this clip path.
    pub clip_path: Option<Arc<ClipPath>>,
    /// The clip geometry.
    pub root: Group,
}

impl ClipPath {
    /// A clip to the rectangle `r` (in the clipped group's coordinates).
    pub fn rect(r: Rect) -> ClipPath {
        ClipPath {
            id: String::new(),
            transform: Affine::IDENTITY,
            clip_path: None,
            root: Group {
                children: vec![Node::Path(PathNode::new(
                    String::new(),
                    r.to_path(0.1),
                    Some(Fill::solid(Color::WHITE)),
                    None,
                ))],
                ..Group::new()
            },
        }
    }
}

/// Whether a mask uses luminance or alpha.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum MaskKind {
    /// Luminance mask.
    #[default]
    Luminance,
    /// Alpha mask.
    Alpha,
}

/// A mask.
#[derive(Clone, Debug)]
pub struct Mask {
    /// Element id.
    pub id: String,
    /// The mask region in user space.
    pub rect: Rect,
    /// Luminance or alpha.
    pub kind: MaskKind,
    /// A mask applied to this mask.
    pub mask: Option<Arc<Mask>>,
    /// The mask content.
    pub root: Group,
}

impl Scene {
    /// The node of an animated unit.
    pub fn unit_node(&self, shape: usize) -> Option<&Node> {
        let path = &self.shapes.get(shape)?.node_path;
        let (last, parents) = path.split_last()?;
        let mut group = &self.root;
        for &i in parents {
            match group.children.get(i)? {
                Node::Group(g) => group = g,
                Node::Path(_) | Node::Image(_) => return None,
            }
        }
        group.children.get(*last)
    }

    /// The canvas rectangle.
    pub fn canvas(&self) -> Rect {
        Rect::new(0.0, 0.0, self.width, self.height)
    }
}

impl PathNode {
    /// A path painted with `fill` and `stroke`, the fill first, that is not (yet) an
    /// animated unit.
    pub fn new(
        id: impl Into<String>,
        path: BezPath,
        fill: Option<Fill>,
        stroke: Option<Stroke>,
    ) -> PathNode {
        PathNode {
            id: id.into(),
            path,
            fill,
            stroke,
            stroke_first: false,
            unit: None,
        }
    }
}

impl Fill {
    /// An opaque non-zero fill of one colour.
    pub fn solid(color: Color) -> Fill {
        Fill {
            paint: Paint::Solid(color),
            opacity: 1.0,
            rule: FillRule::NonZero,
        }
    }
}

impl Stroke {
    /// An opaque stroke of one colour and width, with SVG's default cap, join and miter
    /// limit and no dashes.
    pub fn solid(color: Color, width: f64) -> Stroke {
        Stroke {
            paint: Paint::Solid(color),
            opacity: 1.0,
            width,
            cap: LineCap::Butt,
            join: LineJoin::Miter,
            miter_limit: 4.0,
            dash: None,
            dash_offset: 0.0,
        }
    }
}

/// Builds a [`Scene`] in code. Each unit added becomes a child of the root and a
/// [`Shape`], measured as an importer measures it ([`measure`]: area centroid, bounds,
/// representative paint), tagged, numbered within its tag in the order added, and drawn
/// in that order.
///
/// ```
/// use gmotion::color::Color;
/// use gmotion::scene::{Fill, SceneBuilder};
/// use kurbo::{Point, Rect, Shape as _};
///
/// let scene = SceneBuilder::new(100.0, 80.0)
///     .path("box", Rect::new(10.0, 10.0, 30.0, 50.0).to_path(0.1), Some(Fill::solid(Color::BLACK)), None)
///     .path("box", Rect::new(60.0, 10.0, 70.0, 20.0).to_path(0.1), None, None)
///     .build();
/// assert_eq!(scene.shapes[1].id, 1);
/// assert!((scene.shapes[0].centroid - Point::new(20.0, 30.0)).hypot() < 1e-9);
/// ```
#[derive(Clone, Debug)]
pub struct SceneBuilder {
    scene: Scene,
    ids: HashMap<String, usize>,
}

impl SceneBuilder {
    /// An empty canvas of `width` × `height` user units.
    pub fn new(width: f64, height: f64) -> SceneBuilder {
        SceneBuilder {
            scene: Scene {
                width,
                height,
                root: Group::new(),
                shapes: Vec::new(),
                time: None,
                keys: Vec::new(),
            },
            ids: HashMap::new(),
        }
    }

    /// Adds `node` (a path or a whole group) as a unit tagged `tag`.
    pub fn unit(self, tag: &str, node: Node) -> SceneBuilder {
        self.unit_under(tag, None, node)
    }

    /// Adds `node` as a unit tagged `tag`, inside `parent` (a group, its children ignored:
    /// the unit becomes its only child) when one is given, as a unit sits inside a layer
    /// whose transform places it.
    pub fn unit_under(mut self, tag: &str, parent: Option<Group>, mut node: Node) -> SceneBuilder {
        let index = self.scene.shapes.len();
        node.set_unit(Some(index));
        let top = self.scene.root.children.len();
        let (parent_transform, node_path) = match &parent {
            Some(g) => (g.transform, vec![top, 0]),
            None => (Affine::IDENTITY, vec![top]),
        };
        let m = measure(&node, parent_transform);
        let id = self.ids.entry(tag.to_string()).or_default();
        self.scene.shapes.push(Shape {
            tag: tag.to_string(),
            aliases: Vec::new(),
            inherited: 0,
            rig: false,
            id: *id,
            group: 0,
            z: index,
            node_path,
            parent_transform,
            centroid: m.map_or(Point::ORIGIN, |m| m.centroid),
            bbox: m.map_or(Rect::ZERO, |m| m.bbox),
            fill: m.map_or(Color::BLACK, |m| m.fill),
            stroke: m.map_or(Color::BLACK, |m| m.stroke),
            stroke_width: m.map_or(1.0, |m| m.stroke_width),
            text: crate::text::TextPlace::default(),
        });
        *id += 1;
        let node = match parent {
            Some(mut g) => {
                g.children = vec![node];
                Node::Group(g)
            }
            None => node,
        };
        self.scene.root.children.push(node);
        self
    }

    /// Adds a path as a unit tagged `tag`.
    pub fn path(
        self,
        tag: &str,
        path: BezPath,
        fill: Option<Fill>,
        stroke: Option<Stroke>,
    ) -> SceneBuilder {
        self.unit(
            tag,
            Node::Path(PathNode::new(String::new(), path, fill, stroke)),
        )
    }

    /// The scene.
    pub fn build(self) -> Scene {
        self.scene
    }
}
