//! Spatial grids of transforms: the n×m part of an animation's n×m×p tensor.
//!
//! A grid covers an area of the canvas with `cols × rows` cells. Each cell holds a product
//! of [`Component`]s sampled at the cell centre from a [`Field`]; a shape reads the cell
//! holding its centroid (nearest), blends the four nearest cells (bilinear), or samples the
//! field at its own centroid (exact).

use std::sync::Arc;

use kurbo::{Affine, BezPath, ParamCurveNearest, Point, Rect, Vec2};

use super::component::{Component, product_at};

/// What every grid cell's transform is derived from.
#[derive(Clone, Debug)]
pub enum Field {
    /// The same product of components everywhere (paper: "affine transform").
    Constant(Arc<[Component]>),
    /// A translation from each sample point to a target point ("move towards").
    Towards(Point),
    /// A translation from each sample point to the closest point of a path ("follow path").
    Path(Arc<BezPath>),
}

impl Field {
    /// The components at sample point `p`.
    pub fn sample(&self, p: Point) -> Arc<[Component]> {
        match self {
            Field::Constant(c) => c.clone(),
            Field::Towards(q) => Arc::from([Component::Translate(*q - p)]),
            Field::Path(path) => Arc::from([Component::Translate(closest_point(path, p) - p)]),
        }
    }
}

/// The point of `path` closest to `p` (the path's first point when it has no segments).
pub fn closest_point(path: &BezPath, p: Point) -> Point {
    let mut best: Option<(f64, Point)> = None;
    for seg in path.segments() {
        let n = seg.nearest(p, 1e-6);
        let q = kurbo::ParamCurve::eval(&seg, n.t);
        if best.is_none_or(|(d, _)| n.distance_sq < d) {
            best = Some((n.distance_sq, q));
        }
    }
    best.map(|b| b.1)
        .or_else(|| path.elements().first().and_then(|e| e.end_point()))
        .unwrap_or(p)
}

/// How a shape picks its transform from a grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Lookup {
    /// The cell that holds the centroid (the paper's choice).
    #[default]
    Nearest,
    /// A bilinear blend of the four nearest cell centres.
    Bilinear,
    /// The field sampled at the centroid itself (an infinitely fine grid).
    Exact,
    /// Every vertex of the shape reads the grid bilinearly: the shape deforms.
    Vertex,
}

/// An n×m grid over an area of the canvas.
#[derive(Clone, Debug)]
pub struct Grid {
    /// Columns (n).
    pub cols: usize,
    /// Rows (m).
    pub rows: usize,
    /// The area the grid covers (the canvas).
    pub area: Rect,
    /// Where cell values come from.
    pub field: Field,
    /// Cell values, row-major, sampled at cell centres.
    cells: Vec<Arc<[Component]>>,
    /// The one lookup result of a constant field.
    constant: Option<Blend>,
    /// Carries the grid's own frame onto the canvas (see [`Grid::framed`]).
    frame: Affine,
}

/// Components with weights: the result of a grid lookup. Shared, since every segment of a
/// motion and every shape reading a constant grid holds the same one.
pub type Blend = Arc<[(f64, Arc<[Component]>)]>;

impl Grid {
    /// Samples `field` at the centres of a `cols × rows` grid over `area`.
    pub fn new(cols: usize, rows: usize, area: Rect, field: Field) -> Grid {
        let cols = cols.max(1);
        let rows = rows.max(1);
        let cells = match &field {
            Field::Constant(c) => vec![c.clone()],
            _ => (0..rows)
                .flat_map(|r| (0..cols).map(move |c| (c, r)))
                .map(|(c, r)| field.sample(cell_center(area, cols, rows, c, r)))
                .collect(),
        };
        let constant = match &field {
            Field::Constant(c) => Some(Arc::from([(1.0, c.clone())])),
            _ => None,
        };
        Grid {
            cols,
            rows,
            area,
            field,
            cells,
            constant,
            frame: Affine::IDENTITY,
        }
    }

    /// This grid with its frame carried by `g`: a per-vertex motion read through it acts as
    /// `frame·D·frame⁻¹` (it deforms points in the frame it began in, wherever the motions
    /// outer to it have since taken that frame), as a rigid motion is conjugated by its frame.
    pub fn framed(&self, g: Affine) -> Grid {
        Grid {
            frame: g * self.frame,
            ..self.clone()
        }
    }

    /// The frame that carries this grid's motion onto the canvas (identity when new).
    pub fn frame(&self) -> Affine {
        self.frame
    }

    /// Identifies the grid across [`Grid::framed`] copies: the motion it was built for.
    pub fn key(&self) -> *const () {
        Arc::as_ptr(&self.cells[0]).cast::<()>()
    }

    fn cell(&self, c: usize, r: usize) -> &Arc<[Component]> {
        if self.cells.len() == 1 {
            &self.cells[0]
        } else {
            &self.cells[r * self.cols + c]
        }
    }

    /// Continuous cell coordinates of `p` (cell centres at integers).
    fn grid_coords(&self, p: Point) -> Vec2 {
        let w = self.area.width().max(f64::MIN_POSITIVE);
        let h = self.area.height().max(f64::MIN_POSITIVE);
        Vec2::new(
            (p.x - self.area.x0) / w * self.cols as f64 - 0.5,
            (p.y - self.area.y0) / h * self.rows as f64 - 0.5,
        )
    }

    /// The components a shape with centroid `p` reads, with their weights.
    pub fn lookup(&self, p: Point, mode: Lookup) -> Blend {
        if let Some(b) = &self.constant {
            return b.clone();
        }
        let g = self.grid_coords(p);
        let clampc = |v: f64| (v.round().max(0.0) as usize).min(self.cols - 1);
        let clampr = |v: f64| (v.round().max(0.0) as usize).min(self.rows - 1);
        match mode {
            Lookup::Nearest => Arc::from([(1.0, self.cell(clampc(g.x), clampr(g.y)).clone())]),
            Lookup::Exact => Arc::from([(1.0, self.field.sample(p))]),
            Lookup::Bilinear | Lookup::Vertex => {
                let gx = g.x.clamp(0.0, (self.cols - 1) as f64);
                let gy = g.y.clamp(0.0, (self.rows - 1) as f64);
                let (c0, r0) = (gx.floor() as usize, gy.floor() as usize);
                let (c1, r1) = ((c0 + 1).min(self.cols - 1), (r0 + 1).min(self.rows - 1));
                let (fx, fy) = (gx - c0 as f64, gy - r0 as f64);
                let mut out = Vec::with_capacity(4);
                for (c, r, w) in [
                    (c0, r0, (1.0 - fx) * (1.0 - fy)),
                    (c1, r0, fx * (1.0 - fy)),
                    (c0, r1, (1.0 - fx) * fy),
                    (c1, r1, fx * fy),
                ] {
                    if w > 1e-12 {
                        out.push((w, self.cell(c, r).clone()));
                    }
                }
                out.into()
            }
        }
    }
}

fn cell_center(area: Rect, cols: usize, rows: usize, c: usize, r: usize) -> Point {
    Point::new(
        area.x0 + (c as f64 + 0.5) * area.width() / cols as f64,
        area.y0 + (r as f64 + 0.5) * area.height() / rows as f64,
    )
}

/// A blended transform at progress `s`: Σ wᵢ·Πcᵢ(s), each about `pivot`.
#[inline]
pub fn blend_at(blend: &[(f64, Arc<[Component]>)], pivot: Point, s: f64) -> Affine {
    let about = |m: Affine| about(pivot, m);
    if let [(_, c)] = blend {
        return about(product_at(c, s));
    }
    let mut acc = [0.0; 6];
    for (w, c) in blend {
        let m = product_at(c, s).as_coeffs();
        for k in 0..6 {
            acc[k] += w * m[k];
        }
    }
    about(Affine::new(acc))
}

/// `m` about `pivot`: `T(pivot)·m·T(−pivot)`, without the two matrix products.
#[inline]
pub fn about(pivot: Point, m: Affine) -> Affine {
    let [a, b, c, d, e, f] = m.as_coeffs();
    let (x, y) = (pivot.x, pivot.y);
    Affine::new([a, b, c, d, e + x - (a * x + c * y), f + y - (b * x + d * y)])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn towards_cells_point_at_target() {
        let g = Grid::new(
            2,
            2,
            Rect::new(0.0, 0.0, 100.0, 100.0),
            Field::Towards(Point::new(50.0, 50.0)),
        );
        let b = g.lookup(Point::new(10.0, 10.0), Lookup::Nearest);
        assert_eq!(&*b[0].1, &[Component::Translate(Vec2::new(25.0, 25.0))]);
        let e = g.lookup(Point::new(10.0, 10.0), Lookup::Exact);
        assert_eq!(&*e[0].1, &[Component::Translate(Vec2::new(40.0, 40.0))]);
    }

    #[test]
    fn bilinear_weights_sum_to_one() {
        let g = Grid::new(
            4,
            3,
            Rect::new(0.0, 0.0, 400.0, 300.0),
            Field::Towards(Point::ZERO),
        );
        for p in [
            Point::new(0.0, 0.0),
            Point::new(130.0, 170.0),
            Point::new(399.0, 1.0),
        ] {
            let s: f64 = g.lookup(p, Lookup::Bilinear).iter().map(|x| x.0).sum();
            assert!((s - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn about_equals_the_conjugation_product() {
        let m = Affine::new([0.8, -0.3, 0.45, 1.2, 7.0, -4.0]);
        let p = Point::new(130.0, -42.5);
        let want = Affine::translate(p.to_vec2()) * m * Affine::translate(-p.to_vec2());
        for (x, y) in about(p, m).as_coeffs().iter().zip(want.as_coeffs()) {
            assert!((x - y).abs() < 1e-9, "{x} vs {y}");
        }
        // A rotation about p keeps p in place.
        let q = about(p, Affine::rotate(1.1)) * p;
        assert!((q - p).hypot() < 1e-9);
    }

    #[test]
    fn closest_point_on_line() {
        let mut p = BezPath::new();
        p.move_to((0.0, 0.0));
        p.line_to((100.0, 0.0));
        assert!((closest_point(&p, Point::new(30.0, 40.0)) - Point::new(30.0, 0.0)).hypot() < 1e-6);
    }
}
