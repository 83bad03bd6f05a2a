//! A tiny `Copy` 3-vector of f64, the twin of WGSL's `vec3<f64>`: just what the physics
//! needs (sum, difference, scaling, dot and cross products, length, unit vector, rotation
//! about z).
//!
//! Frame (spec §0): x along the table's short side, y along the long side, z up; the cloth
//! is z = 0.

use std::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

use super::fmath::{cos_poly, sin_poly};

/// A 3-vector of f64.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Vec3 {
    /// x component.
    pub x: f64,
    /// y component.
    pub y: f64,
    /// z component.
    pub z: f64,
}

impl Vec3 {
    /// The zero vector.
    pub const ZERO: Vec3 = Vec3::new(0.0, 0.0, 0.0);
    /// The unit vector ẑ (up).
    pub const Z: Vec3 = Vec3::new(0.0, 0.0, 1.0);
    /// The unit vector x̂.
    pub const X: Vec3 = Vec3::new(1.0, 0.0, 0.0);

    /// A vector from its components.
    pub const fn new(x: f64, y: f64, z: f64) -> Vec3 {
        Vec3 { x, y, z }
    }

    /// Dot product.
    pub fn dot(self, o: Vec3) -> f64 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// Cross product `self × o`.
    pub fn cross(self, o: Vec3) -> Vec3 {
        Vec3::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }

    /// Euclidean length `√(v·v)`.
    pub fn norm(self) -> f64 {
        self.dot(self).sqrt()
    }

    /// `v/|v|`; the zero vector stays zero (pooltool's `ptmath.unit_vector` divides by the
    /// norm; a zero norm never reaches it in the paths that use this).
    pub fn unit(self) -> Vec3 {
        let n = self.norm();
        if n > 0.0 {
            self * (1.0 / n)
        } else {
            Vec3::ZERO
        }
    }

    /// The horizontal part `(x, y, 0)`.
    pub fn xy(self) -> Vec3 {
        Vec3::new(self.x, self.y, 0.0)
    }

    /// Rotated counter-clockwise about z by `angle` radians (`Rz(angle)·v`, spec §0), the
    /// cosine and sine by [`cos_poly`] and [`sin_poly`] (the shader's, bit for bit; NaN
    /// beyond |angle| = [`crate::model::fmath::TRIG_BOUND`]).
    pub fn rotate_z(self, angle: f64) -> Vec3 {
        self.rotate_z_cs(cos_poly(angle), sin_poly(angle))
    }

    /// Rotated counter-clockwise about z by the angle whose cosine and sine are `c`, `s`.
    pub fn rotate_z_cs(self, c: f64, s: f64) -> Vec3 {
        Vec3::new(c * self.x - s * self.y, s * self.x + c * self.y, self.z)
    }

    /// Whether every component is finite.
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }
}

/// `ang(v)`: atan2(v_y, v_x) shifted into `[0, 2π)`; `ang(0) = 0` (pooltool's
/// `ptmath.angle`, spec §0).
pub fn angle(v: Vec3) -> f64 {
    let a = v.y.atan2(v.x);
    if a < 0.0 {
        a + 2.0 * std::f64::consts::PI
    } else {
        a
    }
}

impl Add for Vec3 {
    type Output = Vec3;
    fn add(self, o: Vec3) -> Vec3 {
        Vec3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl AddAssign for Vec3 {
    fn add_assign(&mut self, o: Vec3) {
        *self = *self + o;
    }
}

impl Sub for Vec3 {
    type Output = Vec3;
    fn sub(self, o: Vec3) -> Vec3 {
        Vec3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl SubAssign for Vec3 {
    fn sub_assign(&mut self, o: Vec3) {
        *self = *self - o;
    }
}

impl Neg for Vec3 {
    type Output = Vec3;
    fn neg(self) -> Vec3 {
        Vec3::new(-self.x, -self.y, -self.z)
    }
}

impl Mul<f64> for Vec3 {
    type Output = Vec3;
    fn mul(self, k: f64) -> Vec3 {
        Vec3::new(self.x * k, self.y * k, self.z * k)
    }
}

impl Mul<Vec3> for f64 {
    type Output = Vec3;
    fn mul(self, v: Vec3) -> Vec3 {
        Vec3::new(self * v.x, self * v.y, self * v.z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn products_and_norms() {
        let a = Vec3::new(1.0, 2.0, 3.0);
        let b = Vec3::new(-2.0, 0.5, 1.0);
        assert_eq!(a.dot(b), 2.0);
        assert_eq!(Vec3::X.cross(Vec3::new(0.0, 1.0, 0.0)), Vec3::Z);
        assert_eq!(a.cross(b).dot(a), 0.0);
        assert_eq!(Vec3::new(3.0, 4.0, 0.0).norm(), 5.0);
        assert_eq!(Vec3::ZERO.unit(), Vec3::ZERO);
        assert!((Vec3::new(3.0, 4.0, 0.0).unit().norm() - 1.0).abs() < 1e-16);
    }

    #[test]
    fn rotation_and_angle() {
        let v = Vec3::X.rotate_z(std::f64::consts::FRAC_PI_2);
        assert!(v.x.abs() < 1e-16 && (v.y - 1.0).abs() < 1e-16);
        assert_eq!(angle(Vec3::ZERO), 0.0);
        let a = angle(Vec3::new(0.0, -1.0, 0.0));
        assert!((a - 1.5 * std::f64::consts::PI).abs() < 1e-15);
    }
}
