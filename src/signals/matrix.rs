//! Small dense real matrices: just what state-space systems need (products, the matrix
//! exponential, linear solves and the Faddeev–LeVerrier characteristic polynomial).

/// A row-major `n × m` matrix.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Mat {
    pub rows: usize,
    pub cols: usize,
    pub data: Vec<f64>,
}

impl Mat {
    pub fn zeros(rows: usize, cols: usize) -> Mat {
        Mat {
            rows,
            cols,
            data: vec![0.0; rows * cols],
        }
    }

    pub fn identity(n: usize) -> Mat {
        let mut m = Mat::zeros(n, n);
        for i in 0..n {
            m[(i, i)] = 1.0;
        }
        m
    }

    pub fn from_rows(rows: &[Vec<f64>]) -> Mat {
        let cols = rows.first().map_or(0, Vec::len);
        Mat {
            rows: rows.len(),
            cols,
            data: rows.iter().flatten().copied().collect(),
        }
    }

    pub fn mul(&self, o: &Mat) -> Mat {
        let mut out = Mat::zeros(self.rows, o.cols);
        for i in 0..self.rows {
            for k in 0..self.cols {
                let a = self[(i, k)];
                if a == 0.0 {
                    continue;
                }
                for j in 0..o.cols {
                    out.data[i * o.cols + j] += a * o[(k, j)];
                }
            }
        }
        out
    }

    pub fn scaled(&self, k: f64) -> Mat {
        Mat {
            rows: self.rows,
            cols: self.cols,
            data: self.data.iter().map(|v| v * k).collect(),
        }
    }

    pub fn plus(&self, o: &Mat) -> Mat {
        Mat {
            rows: self.rows,
            cols: self.cols,
            data: self.data.iter().zip(&o.data).map(|(a, b)| a + b).collect(),
        }
    }

    /// Max-row-sum norm.
    pub fn norm_inf(&self) -> f64 {
        (0..self.rows)
            .map(|i| (0..self.cols).map(|j| self[(i, j)].abs()).sum::<f64>())
            .fold(0.0, f64::max)
    }

    pub fn trace(&self) -> f64 {
        (0..self.rows.min(self.cols)).map(|i| self[(i, i)]).sum()
    }

    /// `e^M` by scaling and squaring with a Taylor series: scale until `‖M‖ ≤ 1/2`, sum
    /// 20 terms (truncation below 1e-20 relative), square back.
    pub fn expm(&self) -> Mat {
        let norm = self.norm_inf();
        let squarings = if norm > 0.5 {
            (norm / 0.5).log2().ceil() as u32
        } else {
            0
        };
        let a = self.scaled(0.5f64.powi(squarings as i32));
        let mut term = Mat::identity(self.rows);
        let mut sum = Mat::identity(self.rows);
        for k in 1..=20 {
            term = term.mul(&a).scaled(1.0 / k as f64);
            sum = sum.plus(&term);
        }
        for _ in 0..squarings {
            sum = sum.mul(&sum);
        }
        sum
    }

    /// Solves `self · X = b` by Gaussian elimination with partial pivoting; `None` when
    /// the matrix is singular to working precision.
    pub fn solve(&self, b: &Mat) -> Option<Mat> {
        let n = self.rows;
        let mut a = self.clone();
        let mut x = b.clone();
        let scale = self.norm_inf().max(f64::MIN_POSITIVE);
        for col in 0..n {
            let piv = (col..n).max_by(|&i, &j| a[(i, col)].abs().total_cmp(&a[(j, col)].abs()))?;
            if a[(piv, col)].abs() <= 1e-14 * scale {
                return None;
            }
            for j in 0..n {
                a.data.swap(col * n + j, piv * n + j);
            }
            for j in 0..x.cols {
                x.data.swap(col * x.cols + j, piv * x.cols + j);
            }
            for i in col + 1..n {
                let f = a[(i, col)] / a[(col, col)];
                for j in col..n {
                    a.data[i * n + j] -= f * a[(col, j)];
                }
                for j in 0..x.cols {
                    x.data[i * x.cols + j] -= f * x[(col, j)];
                }
            }
        }
        for col in (0..n).rev() {
            for j in 0..x.cols {
                let mut v = x[(col, j)];
                for k in col + 1..n {
                    v -= a[(col, k)] * x[(k, j)];
                }
                x.data[col * x.cols + j] = v / a[(col, col)];
            }
        }
        Some(x)
    }

    /// Faddeev–LeVerrier: the characteristic polynomial `det(λI − M)` (ascending
    /// coefficients, monic) and the matrices `M₁..Mₙ` with
    /// `adj(λI − M) = Σₖ Mₖ λ^(n−k)`.
    pub fn faddeev_leverrier(&self) -> (Vec<f64>, Vec<Mat>) {
        let n = self.rows;
        let mut c = vec![0.0; n + 1];
        c[n] = 1.0;
        let mut mk = Mat::zeros(n, n);
        let mut adj = Vec::with_capacity(n);
        for k in 1..=n {
            mk = self.mul(&mk).plus(&Mat::identity(n).scaled(c[n - k + 1]));
            c[n - k] = -self.mul(&mk).trace() / k as f64;
            adj.push(mk.clone());
        }
        (c, adj)
    }
}

impl std::ops::Index<(usize, usize)> for Mat {
    type Output = f64;
    fn index(&self, (i, j): (usize, usize)) -> &f64 {
        &self.data[i * self.cols + j]
    }
}

impl std::ops::IndexMut<(usize, usize)> for Mat {
    fn index_mut(&mut self, (i, j): (usize, usize)) -> &mut f64 {
        &mut self.data[i * self.cols + j]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expm_of_rotation_generator() {
        let m = Mat::from_rows(&[vec![0.0, -3.0], vec![3.0, 0.0]]).expm();
        assert!((m[(0, 0)] - 3f64.cos()).abs() < 1e-13);
        assert!((m[(1, 0)] - 3f64.sin()).abs() < 1e-13);
    }

    #[test]
    fn charpoly_of_companion() {
        // Companion of x² + 3x + 2.
        let m = Mat::from_rows(&[vec![0.0, 1.0], vec![-2.0, -3.0]]);
        let (c, adj) = m.faddeev_leverrier();
        assert_eq!(c, vec![2.0, 3.0, 1.0]);
        assert_eq!(adj[0], Mat::identity(2));
    }

    #[test]
    fn solve_small_system() {
        let a = Mat::from_rows(&[vec![2.0, 1.0], vec![1.0, 3.0]]);
        let b = Mat::from_rows(&[vec![3.0], vec![5.0]]);
        let x = a.solve(&b).unwrap();
        assert!((x[(0, 0)] - 0.8).abs() < 1e-14 && (x[(1, 0)] - 1.4).abs() < 1e-14);
    }
}
