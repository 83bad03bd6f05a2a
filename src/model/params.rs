//! The physical parameters of a batch and pooltool's defaults.
//!
//! The GPU twin of this file is `shaders/model/params.wgsl` (the uniform the kernels read).

/// Default ball radius in metres: pooltool's `BallParams.R` (a 2¼-inch pool ball).
pub const DEFAULT_RADIUS: f64 = 0.028575;
/// Default sliding friction coefficient ball–cloth: pooltool's `BallParams.u_s`.
pub const DEFAULT_MU_S: f64 = 0.2;
/// Default rolling friction coefficient ball–cloth: pooltool's `BallParams.u_r`.
pub const DEFAULT_MU_R: f64 = 0.01;
/// Default spinning friction coefficient divided by the radius: pooltool's
/// `BallParams.u_sp_proportionality` (`u_sp = 10/9 · R · 0.4 = 0.444 R`).
pub const DEFAULT_MU_SP_PER_RADIUS: f64 = 0.444;
/// Default gravitational acceleration in m/s²: pooltool's `BallParams.g`.
pub const DEFAULT_G: f64 = 9.81;

/// The physical parameters of one batch, in SI units.
///
/// The defaults are pooltool's (`pooltool/objects/ball/params.py`, version 0.6):
/// `R = 0.028575 m`, `μs = 0.2`, `μr = 0.01`, `μsp = 0.444·R`, `g = 9.81 m/s²`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// Ball radius `R` in metres.
    pub radius: f64,
    /// Sliding friction coefficient `μs`.
    pub mu_s: f64,
    /// Rolling friction coefficient `μr`.
    pub mu_r: f64,
    /// Spinning friction coefficient `μsp` (in metres, as in pooltool). It decides how long a
    /// ball spins in place, which never changes where it is, so collision times do not
    /// depend on it; it is validated and carried for the event loop around this crate.
    pub mu_sp: f64,
    /// Gravitational acceleration `g` in m/s².
    pub g: f64,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            radius: DEFAULT_RADIUS,
            mu_s: DEFAULT_MU_S,
            mu_r: DEFAULT_MU_R,
            mu_sp: DEFAULT_MU_SP_PER_RADIUS * DEFAULT_RADIUS,
            g: DEFAULT_G,
        }
    }
}

impl Params {
    /// Checks that every parameter is finite and strictly positive, and so are the
    /// decelerations `μs g` and `μr g` (neither may underflow to 0 or a subnormal, nor
    /// overflow: [`crate::ball_path`] divides by them).
    ///
    /// On failure the error names the first offending parameter (or product).
    pub fn validate(&self) -> Result<(), crate::Error> {
        for (name, value) in [
            ("radius", self.radius),
            ("mu_s", self.mu_s),
            ("mu_r", self.mu_r),
            ("mu_sp", self.mu_sp),
            ("g", self.g),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(crate::Error::Param { name, value });
            }
        }
        for (name, value) in [
            ("mu_s * g", self.mu_s * self.g),
            ("mu_r * g", self.mu_r * self.g),
        ] {
            if !(value.is_normal() && (7.0 * value).is_finite()) {
                return Err(crate::Error::Param { name, value });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn params_validation_names_the_parameter() {
        let bad = Params {
            mu_r: 0.0,
            ..Params::default()
        };
        let err = bad.validate().unwrap_err().to_string();
        assert!(err.contains("mu_r"), "{err}");
        let nan = Params {
            g: f64::NAN,
            ..Params::default()
        };
        assert!(nan.validate().unwrap_err().to_string().contains('g'));
        assert!(Params::default().validate().is_ok());
    }
}
