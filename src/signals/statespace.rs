//! Linear systems in state-space form (paper sec. 6, Definition 5):
//! `ẋ = Ax + Bu`, `y = Cx + Du`, single input and output (vector signals run one copy
//! per component), and their exact zero-order-hold discretisation.

use super::complex::Complex;
use super::error::{SignalError, finite, positive};
use super::matrix::Mat;
use super::poly;
use super::spring::Spring;
use super::system::System;
use super::vector::Vector;

/// Largest state dimension accepted (the numerics — characteristic polynomials, roots —
/// are meant for the small systems animation uses).
pub const MAX_ORDER: usize = 16;

/// A continuous-time single-input single-output system `ẋ = Ax + Bu`, `y = Cx + Du`.
#[derive(Clone, Debug, PartialEq)]
pub struct StateSpace {
    pub(crate) a: Mat,
    pub(crate) b: Vec<f64>,
    pub(crate) c: Vec<f64>,
    pub(crate) d: f64,
}

impl StateSpace {
    /// A system from its matrices: `a` is `n × n` (rows), `b` and `c` have `n` entries.
    /// Rejects non-finite entries, mismatched sizes, `n` outside `1..=16`, and systems
    /// with an eigenvalue of `A` whose real part is not negative (they never settle).
    pub fn new(
        a: Vec<Vec<f64>>,
        b: Vec<f64>,
        c: Vec<f64>,
        d: f64,
    ) -> Result<StateSpace, SignalError> {
        let n = a.len();
        if n == 0 || n > MAX_ORDER {
            return Err(SignalError::Invalid(format!(
                "a state-space system needs 1 to {MAX_ORDER} states, got {n}"
            )));
        }
        if a.iter().any(|row| row.len() != n) || b.len() != n || c.len() != n {
            return Err(SignalError::Invalid(format!(
                "state-space sizes do not match: A must be {n}×{n}, B and C must have {n} entries"
            )));
        }
        for v in a
            .iter()
            .flatten()
            .chain(&b)
            .chain(&c)
            .chain(std::iter::once(&d))
        {
            finite("state-space matrix entry", *v)?;
        }
        let ss = StateSpace {
            a: Mat::from_rows(&a),
            b,
            c,
            d,
        };
        for p in ss.poles() {
            if p.re >= 0.0 || p.re.is_nan() {
                return Err(SignalError::Unstable {
                    domain: "continuous-time",
                    re: p.re,
                    im: p.im,
                    hint: "every eigenvalue of A needs a negative real part",
                });
            }
        }
        Ok(ss)
    }

    /// The spring–mass–damper in the paper's state variables (position `x`, velocity
    /// `q`): `A = [[0, 1], [−k/m, −c/m]]`, `B = [0, k/m]`, `C = [1, 0]`, `D = 0`.
    pub fn spring(spring: &Spring) -> StateSpace {
        let (m, k, c) = (spring.mass(), spring.stiffness(), spring.damping());
        StateSpace {
            a: Mat::from_rows(&[vec![0.0, 1.0], vec![-k / m, -c / m]]),
            b: vec![0.0, k / m],
            c: vec![1.0, 0.0],
            d: 0.0,
        }
    }

    /// The number of states.
    pub fn order(&self) -> usize {
        self.b.len()
    }

    /// `A` as rows.
    pub fn a(&self) -> Vec<Vec<f64>> {
        self.a
            .data
            .chunks(self.a.cols)
            .map(<[f64]>::to_vec)
            .collect()
    }

    /// `B`.
    pub fn b(&self) -> &[f64] {
        &self.b
    }

    /// `C`.
    pub fn c(&self) -> &[f64] {
        &self.c
    }

    /// `D`.
    pub fn d(&self) -> f64 {
        self.d
    }

    /// The eigenvalues of `A` (roots of its characteristic polynomial).
    pub fn poles(&self) -> Vec<Complex> {
        poly::roots(&self.a.faddeev_leverrier().0)
    }

    /// The transfer function `C(sI − A)⁻¹B + D` as numerator and denominator
    /// coefficients in ascending powers of `s` (denominator monic).
    pub fn transfer_function(&self) -> (Vec<f64>, Vec<f64>) {
        let n = self.order();
        let (den, adj) = self.a.faddeev_leverrier();
        let mut num: Vec<f64> = den.iter().map(|v| v * self.d).collect();
        for (k, m) in adj.iter().enumerate() {
            // adj(sI − A) = Σ_{k=1..n} M_k s^(n−k)
            let cmb: f64 = (0..n)
                .map(|i| self.c[i] * (0..n).map(|j| m[(i, j)] * self.b[j]).sum::<f64>())
                .sum();
            num[n - (k + 1)] += cmb;
        }
        (num, den)
    }

    /// The gain at DC, `D − C·A⁻¹·B` (1 for an affine system).
    pub fn dc_gain(&self) -> f64 {
        let b = Mat {
            rows: self.order(),
            cols: 1,
            data: self.b.clone(),
        };
        match self.a.solve(&b) {
            Some(x) => self.d - self.c.iter().zip(&x.data).map(|(c, x)| c * x).sum::<f64>(),
            None => f64::NAN,
        }
    }

    /// `(e^{AT}, ∫₀ᵀ e^{Aτ}dτ·B)` from one exponential of the augmented matrix
    /// `[[A, B], [0, 0]]·T` (Van Loan).
    pub(crate) fn exp_pair(&self, t: f64) -> (Mat, Vec<f64>) {
        let n = self.order();
        let mut m = Mat::zeros(n + 1, n + 1);
        for i in 0..n {
            for j in 0..n {
                m[(i, j)] = self.a[(i, j)] * t;
            }
            m[(i, n)] = self.b[i] * t;
        }
        let e = m.expm();
        let mut ad = Mat::zeros(n, n);
        for i in 0..n {
            for j in 0..n {
                ad[(i, j)] = e[(i, j)];
            }
        }
        (ad, (0..n).map(|i| e[(i, n)]).collect())
    }

    /// The exact output at `t` after a unit step of the input at `t = 0`, from rest at 0.
    pub fn step_response(&self, t: f64) -> f64 {
        if t <= 0.0 {
            return 0.0;
        }
        let (_, x) = self.exp_pair(t);
        self.c.iter().zip(&x).map(|(c, x)| c * x).sum::<f64>() + self.d
    }

    /// Exact discretisation for inputs held constant over each frame (zero-order hold,
    /// a.k.a. step invariance): `A_d = e^{AT}`, `B_d = ∫₀ᵀ e^{Aτ}dτ·B`, `C_d = C`,
    /// `D_d = D`. For step inputs that change on frames the samples equal the continuous
    /// output exactly (the paper's "difference equations that trace the same path").
    pub fn discretize_zoh<V: Vector>(
        &self,
        fps: f64,
    ) -> Result<DiscreteStateSpace<V>, SignalError> {
        positive("frame rate", fps)?;
        let (ad, bd) = self.exp_pair(1.0 / fps);
        DiscreteStateSpace::new(ad, bd, self.c.clone(), self.d)
    }
}

/// A discrete-time state-space system `x[n+1] = A_d x[n] + B_d u[n]`,
/// `y[n] = C x[n] + D u[n]`, run on vector signals component by component. Cost per
/// sample is `O(n²)` in the state size; [`super::BiquadCascade`] is the `O(n)` way to run
/// the same system.
#[derive(Clone, Debug)]
pub struct DiscreteStateSpace<V> {
    ad: Mat,
    bd: Vec<f64>,
    c: Vec<f64>,
    d: f64,
    /// State at rest per unit of constant input: `(I − A_d)⁻¹ B_d`.
    rest: Vec<f64>,
    state: Vec<V>,
}

impl<V: Vector> DiscreteStateSpace<V> {
    fn new(
        ad: Mat,
        bd: Vec<f64>,
        c: Vec<f64>,
        d: f64,
    ) -> Result<DiscreteStateSpace<V>, SignalError> {
        let n = bd.len();
        for p in poly::roots(&ad.faddeev_leverrier().0) {
            if p.abs() >= 1.0 {
                return Err(SignalError::Unstable {
                    domain: "discrete-time",
                    re: p.re,
                    im: p.im,
                    hint: "every eigenvalue of A_d needs modulus below 1",
                });
            }
        }
        let i_minus = Mat::identity(n).plus(&ad.scaled(-1.0));
        let rest = i_minus
            .solve(&Mat {
                rows: n,
                cols: 1,
                data: bd.clone(),
            })
            .ok_or_else(|| SignalError::Invalid("the discretised system has no rest state".into()))?
            .data;
        Ok(DiscreteStateSpace {
            ad,
            bd,
            c,
            d,
            rest,
            state: vec![V::zero(); n],
        })
    }

    /// The number of states.
    pub fn order(&self) -> usize {
        self.bd.len()
    }
}

impl<V: Vector> System<V> for DiscreteStateSpace<V> {
    fn step(&mut self, u: V) -> V {
        let n = self.order();
        let mut y = u.scale(self.d);
        for i in 0..n {
            y = y.add_scaled(self.state[i], self.c[i]);
        }
        let next: Vec<V> = (0..n)
            .map(|i| {
                let mut v = u.scale(self.bd[i]);
                for j in 0..n {
                    v = v.add_scaled(self.state[j], self.ad[(i, j)]);
                }
                v
            })
            .collect();
        self.state = next;
        y
    }

    fn reset(&mut self, x: V) {
        for (s, r) in self.state.iter_mut().zip(&self.rest) {
            *s = x.scale(*r);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spring_state_space_matches_closed_form() {
        let s = Spring::from_duration_bounce(0.6, 0.3).unwrap();
        let ss = StateSpace::spring(&s);
        for t in [0.05, 0.3, 0.9, 2.0] {
            assert!((ss.step_response(t) - s.step_state(t).0).abs() < 1e-12);
        }
        assert!((ss.dc_gain() - 1.0).abs() < 1e-12);
        let (num, den) = ss.transfer_function();
        let k = s.stiffness();
        assert!((num[0] - k).abs() < 1e-9 * k && num[1].abs() < 1e-9 * k);
        assert!((den[0] - k).abs() < 1e-9 * k && (den[2] - 1.0).abs() < 1e-12);
    }

    #[test]
    fn invalid_systems_are_rejected() {
        let unstable = StateSpace::new(vec![vec![0.5]], vec![1.0], vec![1.0], 0.0);
        assert!(matches!(unstable, Err(SignalError::Unstable { .. })));
        let marginal = StateSpace::new(
            vec![vec![0.0, 1.0], vec![-4.0, 0.0]],
            vec![0.0, 1.0],
            vec![4.0, 0.0],
            0.0,
        );
        assert!(marginal.is_err());
        assert!(StateSpace::new(vec![vec![-1.0, 0.0]], vec![1.0], vec![1.0], 0.0).is_err());
        assert!(StateSpace::new(vec![vec![f64::NAN]], vec![1.0], vec![1.0], 0.0).is_err());
    }

    #[test]
    fn zoh_traces_the_continuous_step_response() {
        let s = Spring::from_duration_bounce(0.5, 0.2).unwrap();
        let ss = StateSpace::spring(&s);
        let mut sys: DiscreteStateSpace<f64> = ss.discretize_zoh(60.0).unwrap();
        sys.reset(0.0);
        for n in 0..120 {
            let y = sys.step(1.0);
            assert!((y - s.step_state(n as f64 / 60.0).0).abs() < 1e-12);
        }
    }
}
