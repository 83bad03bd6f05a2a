//! Parameters of the simulation, with pooltool 0.6.0's defaults (spec §1).
//!
//! - [`BallParams`]: one ball set's physical constants (`objects/ball/params.py`,
//!   `BallParams`, spec §1.1). Every ball of a table shares them (pooltool's `System`
//!   validator demands one m and R).
//! - [`CueParams`]: the cue stick (`objects/cue/datatypes.py`, spec §1.2).
//! - [`ResolverParams`]: the default resolver's constants (`resolver.yaml` version 9,
//!   spec §1.3–1.4).
//! - [`SimParams`]: all three together, as the event loop takes them.

use crate::error::SimError;

/// pooltool's `constants.EPS`: 100 machine epsilons (spec §0).
pub const EPS: f64 = 100.0 * f64::EPSILON;
/// pooltool's `constants.MIN_DIST`: the spacer every `make_kiss` leaves (spec §1.4, Q1).
pub const MIN_DIST: f64 = 1e-6;
/// The tolerance of pooltool's transition assertions (`physics/resolve/transition`,
/// spec §1.4); here only documented, as the transitions zero the components (Q12).
pub const TRANSITION_TOL: f64 = 1e-12;

/// pooltool's default `u_sp_proportionality` (`10 * 2 / 5 / 9`): the spinning friction
/// μ_sp is this times R (spec §1.1).
pub const DEFAULT_U_SP_PROPORTIONALITY: f64 = 10.0 * 2.0 / 5.0 / 9.0;

/// A ball's physical constants (spec §1.1), in SI units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BallParams {
    /// Mass `m` in kg.
    pub m: f64,
    /// Radius `R` in m.
    pub r: f64,
    /// Sliding friction with the cloth, μ_s.
    pub u_s: f64,
    /// Rolling resistance, μ_r.
    pub u_r: f64,
    /// Spinning friction μ_sp, a length in m (`u_sp_proportionality · R`).
    pub u_sp: f64,
    /// Ball–ball friction μ_b; unused by the default model (the Alciatore curve replaces
    /// it, spec §5.2), carried for completeness.
    pub u_b: f64,
    /// Ball–ball restitution e_b.
    pub e_b: f64,
    /// Cushion restitution e_c (Stronge's e_n).
    pub e_c: f64,
    /// Cushion friction f_c (Stronge's μ).
    pub f_c: f64,
    /// Gravity g in m/s².
    pub g: f64,
}

impl Default for BallParams {
    /// pooltool's `BallParams` class defaults (POOL_GENERIC).
    fn default() -> Self {
        let r = 0.028575;
        BallParams {
            m: 0.170097,
            r,
            u_s: 0.2,
            u_r: 0.01,
            u_sp: DEFAULT_U_SP_PROPORTIONALITY * r,
            u_b: 0.05,
            e_b: 0.95,
            e_c: 0.85,
            f_c: 0.2,
            g: 9.81,
        }
    }
}

impl BallParams {
    /// pooltool's `PrebuiltBallParams.SNOOKER_GENERIC` (`objects/ball/params.py`), the
    /// balls of `GameType.SNOOKER`: m 0.140 kg, R 26.19375 mm (2 1/16 in), u_s 0.5,
    /// f_c 0.5; the rest the class defaults.
    pub fn snooker() -> Self {
        let r = 0.02619375;
        BallParams {
            m: 0.140,
            r,
            u_s: 0.5,
            u_sp: DEFAULT_U_SP_PROPORTIONALITY * r,
            f_c: 0.5,
            ..BallParams::default()
        }
    }

    /// pooltool's `PrebuiltBallParams.BILLIARD_GENERIC`, the balls of
    /// `GameType.THREECUSHION` (carom): m 0.210 kg, R 30.75 mm (61.5 mm across), f_c 0.15;
    /// the rest the class defaults.
    pub fn carom() -> Self {
        let r = 0.0615 / 2.0;
        BallParams {
            m: 0.210,
            r,
            u_sp: DEFAULT_U_SP_PROPORTIONALITY * r,
            f_c: 0.15,
            ..BallParams::default()
        }
    }

    /// Checks that every constant is finite, the positive ones (m, R, μ_s, μ_r, μ_sp, g)
    /// strictly positive, as are the decelerations μ_s g, μ_r g, μ_sp g (no underflow to 0),
    /// the restitutions in `(0, 1]` and the friction coefficients u_b and f_c positive (as
    /// pooltool's `BallParams` asks: its cushion model divides by f_c; FUZZING.md, finding
    /// 19), all normal f64. The error names the first bad field.
    pub fn validate(&self) -> Result<(), SimError> {
        for (name, v) in [
            ("m", self.m),
            ("R", self.r),
            ("u_s", self.u_s),
            ("u_r", self.u_r),
            ("u_sp", self.u_sp),
            ("g", self.g),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(SimError::Param { name, value: v });
            }
        }
        // each is positive; their products, the decelerations, must be normal f64 (as
        // `Params::validate` asks): one that underflows to a subnormal (g = 1e-320) made
        // every motion time v / (μ g) infinite, and a moving ball never stopped, with no
        // event and no cut (the `event_loop` fuzz target's finding 11, FUZZING.md)
        for (name, v) in [
            ("u_s * g", self.u_s * self.g),
            ("u_r * g", self.u_r * self.g),
            ("u_sp * g", self.u_sp * self.g),
        ] {
            if !v.is_normal() {
                return Err(SimError::Param { name, value: v });
            }
        }
        // the moment of inertia 2/5 m R² and the spin deceleration 5 μ_sp g / (2R) too: a
        // subnormal R (1e-320) made every spin v / R infinite and a state NaN (the
        // `event_loop` fuzz target's finding 12, FUZZING.md)
        for (name, v) in [
            ("m * R^2", 0.4 * self.m * self.r * self.r),
            ("u_sp * g / R", self.spin_decel()),
            ("1 / R", 1.0 / self.r),
        ] {
            if !v.is_normal() {
                return Err(SimError::Param { name, value: v });
            }
        }
        // normal f64: a subnormal e_c (1e-320) made Stronge's cushion model divide into
        // NaN (the `event_loop` fuzz target's finding 17, FUZZING.md)
        for (name, v) in [("e_b", self.e_b), ("e_c", self.e_c)] {
            if !(v.is_normal() && v > 0.0 && v <= 1.0) {
                return Err(SimError::Param { name, value: v });
            }
        }
        // positive, as pooltool's validator asks: f_c = 0 gave a ball a sliding
        // acceleration of ~1e-14 along a rail after a frictionless cushion, and pooltool's
        // quadratic (copied, Q6) then lost the root to cancellation and put the next
        // cushion event R beyond the rail (the `event_loop` fuzz target's finding 19)
        for (name, v) in [("u_b", self.u_b), ("f_c", self.f_c)] {
            if !(v.is_normal() && v > 0.0) {
                return Err(SimError::Param { name, value: v });
            }
        }
        Ok(())
    }

    /// The spin angular deceleration α_sp = 5 μ_sp g / (2R) in rad/s² (spec §1.1).
    pub fn spin_decel(&self) -> f64 {
        5.0 * self.u_sp * self.g / (2.0 * self.r)
    }
}

/// The cue stick's constants that the strike uses (spec §1.2, §5.6).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CueParams {
    /// Cue mass M in kg (`CueSpecs.M`).
    pub mass: f64,
    /// The cue's end mass m_e in kg (`CueSpecs.end_mass`), for squirt.
    pub end_mass: f64,
    /// `english_throttle` of `instantaneous_point` (scales ω).
    pub english_throttle: f64,
    /// `squirt_throttle` of `instantaneous_point` (scales the squirt angle).
    pub squirt_throttle: f64,
}

impl Default for CueParams {
    fn default() -> Self {
        CueParams {
            mass: 0.567,
            end_mass: 0.170097 / 30.0,
            english_throttle: 1.0,
            squirt_throttle: 1.0,
        }
    }
}

impl CueParams {
    /// Checks that both masses are finite and positive and the throttles finite.
    pub fn validate(&self) -> Result<(), SimError> {
        for (name, v) in [("cue mass", self.mass), ("cue end_mass", self.end_mass)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(SimError::Param { name, value: v });
            }
        }
        for (name, v) in [
            ("english_throttle", self.english_throttle),
            ("squirt_throttle", self.squirt_throttle),
        ] {
            if !v.is_finite() {
                return Err(SimError::Param { name, value: v });
            }
        }
        Ok(())
    }
}

/// The default resolver's constants (spec §1.3, §1.4, §5.2, §5.4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResolverParams {
    /// Alciatore ball–ball friction `μ_b = a + b·exp(−c·|slip|)`: a.
    pub alciatore_a: f64,
    /// Alciatore b.
    pub alciatore_b: f64,
    /// Alciatore c (s/m).
    pub alciatore_c: f64,
    /// `stronge_compliant`'s omega_ratio (the yaml's 1.8, not the class default 1.7).
    pub omega_ratio: f64,
    /// Stronge tangential compliance factor β_t.
    pub beta_t: f64,
    /// Stronge normal compliance factor β_n.
    pub beta_n: f64,
    /// Stronge normal stiffness k_n in N/m.
    pub k_n: f64,
    /// The make_kiss spacer s in m (`MIN_DIST`).
    pub spacer: f64,
}

impl Default for ResolverParams {
    fn default() -> Self {
        ResolverParams {
            alciatore_a: 0.009951,
            alciatore_b: 0.108,
            alciatore_c: 1.088,
            omega_ratio: 1.8,
            beta_t: 3.5,
            beta_n: 1.0,
            k_n: 1000.0,
            spacer: MIN_DIST,
        }
    }
}

impl ResolverParams {
    /// Stronge's η² = (β_t/β_n)/omega_ratio² (spec §1.4).
    pub fn eta2(&self) -> f64 {
        (self.beta_t / self.beta_n) / (self.omega_ratio * self.omega_ratio)
    }

    /// Checks that every constant is finite and the ones that divide positive.
    pub fn validate(&self) -> Result<(), SimError> {
        for (name, v) in [
            ("omega_ratio", self.omega_ratio),
            ("beta_t", self.beta_t),
            ("beta_n", self.beta_n),
            ("k_n", self.k_n),
            ("spacer", self.spacer),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(SimError::Param { name, value: v });
            }
        }
        for (name, v) in [
            ("alciatore_a", self.alciatore_a),
            ("alciatore_b", self.alciatore_b),
            ("alciatore_c", self.alciatore_c),
        ] {
            if !v.is_finite() {
                return Err(SimError::Param { name, value: v });
            }
        }
        Ok(())
    }
}

/// Everything the event loop needs besides the table and the balls.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SimParams {
    /// The balls' constants (shared by every ball).
    pub ball: BallParams,
    /// The cue's constants.
    pub cue: CueParams,
    /// The resolver's constants.
    pub resolver: ResolverParams,
}

impl SimParams {
    /// Validates all three parts.
    pub fn validate(&self) -> Result<(), SimError> {
        self.ball.validate()?;
        self.cue.validate()?;
        self.resolver.validate()
    }
}

/// The physics of a batch of tables: one parameter set for all of them, or one for each
/// (per-table physics: a study can draw the cloth's and the cushions' parameters per sample
/// as it draws the cue's noise), given as a slice or drawn on demand.
#[derive(Clone, Copy)]
pub enum Physics<'a> {
    /// Every table with these parameters.
    Shared(SimParams),
    /// Table `k` with `[k]`; the slice has one entry per table of the batch.
    PerTable(&'a [SimParams]),
    /// Table `k` with `draw(offset + k)`: parameters made per table when needed (a study's
    /// draws), never held for the whole batch. `draw` must return the same set for the same
    /// table every time it is called (it is called more than once a table).
    Drawn {
        /// Table `offset + k`'s parameters.
        draw: &'a (dyn Fn(usize) -> SimParams + Sync),
        /// The batch's first table in `draw`'s numbering.
        offset: usize,
    },
}

impl std::fmt::Debug for Physics<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Physics::Shared(p) => f.debug_tuple("Shared").field(p).finish(),
            Physics::PerTable(all) => f.debug_tuple("PerTable").field(all).finish(),
            Physics::Drawn { offset, .. } => f
                .debug_struct("Drawn")
                .field("offset", offset)
                .finish_non_exhaustive(),
        }
    }
}

impl<'a> Physics<'a> {
    /// Parameters drawn per table by `draw(k)` ([`Physics::Drawn`]).
    pub fn drawn(draw: &'a (dyn Fn(usize) -> SimParams + Sync)) -> Physics<'a> {
        Physics::Drawn { draw, offset: 0 }
    }
}

impl Physics<'_> {
    /// Table `k`'s parameters (for `PerTable`, `k` must be a table of the slice).
    pub fn of(&self, k: usize) -> SimParams {
        match self {
            Physics::Shared(p) => *p,
            Physics::PerTable(all) => all[k],
            Physics::Drawn { draw, offset } => draw(offset + k),
        }
    }

    /// Checks them for a batch of `n_tables` tables: one set per table where per table, each
    /// valid ([`SimParams::validate`]); the error names the first bad table's position.
    /// Drawn sets are drawn and checked here (Rayon over tables).
    pub fn check(&self, n_tables: usize) -> Result<(), (usize, SimError)> {
        match self {
            Physics::Shared(p) => p.validate().map_err(|e| (0, e)),
            Physics::PerTable(all) => {
                if all.len() < n_tables {
                    return Err((
                        all.len(),
                        SimError::Table(format!(
                            "no physics for this table: {} parameter sets for {n_tables} tables",
                            all.len()
                        )),
                    ));
                }
                for (k, p) in all[..n_tables].iter().enumerate() {
                    p.validate().map_err(|e| (k, e))?;
                }
                Ok(())
            }
            Physics::Drawn { .. } => {
                use rayon::prelude::*;
                let bad = (0..n_tables)
                    .into_par_iter()
                    .with_min_len(1024)
                    .find_first(|&k| self.of(k).validate().is_err());
                match bad {
                    Some(k) => self.of(k).validate().map_err(|e| (k, e)),
                    None => Ok(()),
                }
            }
        }
    }

    /// The physics of tables `range` (for a chunk of the batch).
    pub fn part(&self, range: std::ops::Range<usize>) -> Self {
        match *self {
            Physics::Shared(p) => Physics::Shared(p),
            Physics::PerTable(all) => Physics::PerTable(&all[range]),
            Physics::Drawn { draw, offset } => Physics::Drawn {
                draw,
                offset: offset + range.start,
            },
        }
    }

    /// The first table's parameters (the defaults for an empty per-table list): what an
    /// event loop starts with.
    pub fn first(&self) -> SimParams {
        match self {
            Physics::Shared(p) => *p,
            Physics::PerTable(all) => all.first().copied().unwrap_or_default(),
            Physics::Drawn { .. } => self.of(0),
        }
    }

    /// Whether the tables share one set.
    pub fn is_shared(&self) -> bool {
        matches!(self, Physics::Shared(_))
    }
}

impl From<SimParams> for Physics<'_> {
    fn from(p: SimParams) -> Self {
        Physics::Shared(p)
    }
}

impl<'a> From<&'a [SimParams]> for Physics<'a> {
    fn from(all: &'a [SimParams]) -> Self {
        Physics::PerTable(all)
    }
}

impl<'a> From<&'a Vec<SimParams>> for Physics<'a> {
    fn from(all: &'a Vec<SimParams>) -> Self {
        Physics::PerTable(all)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_pooltools() {
        let p = BallParams::default();
        assert!((p.u_sp - 0.0127).abs() < 1e-15);
        // the constant is the expression the default has always used, bit for bit
        assert_eq!(p.u_sp.to_bits(), (10.0 * 2.0 / 5.0 / 9.0 * p.r).to_bits());
        assert_eq!(p.u_sp, 0.0127);
        assert!((p.spin_decel() - 10.9).abs() < 1e-12);
        let r = ResolverParams::default();
        assert!((r.eta2() - 1.0802469135802468).abs() < 1e-16);
        assert!((0.170097 / CueParams::default().end_mass - 30.0).abs() < 1e-13);
        assert!(SimParams::default().validate().is_ok());
        assert_eq!(EPS, 2.220446049250313e-14);
    }

    #[test]
    fn validation_names_the_field() {
        let bad = BallParams {
            e_c: 1.5,
            ..BallParams::default()
        };
        assert!(bad.validate().unwrap_err().to_string().contains("e_c"));
        let bad = BallParams {
            r: f64::NAN,
            ..BallParams::default()
        };
        assert!(bad.validate().unwrap_err().to_string().contains('R'));
    }
}
