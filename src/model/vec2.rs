//! 2-D vectors: just what the path algebra needs.
//!
//! The GPU twin of this file is `shaders/model/vec2.wgsl` (WGSL's own `vec2` type with the
//! same helper functions).

use std::ops::{Add, Mul, Neg, Sub};

/// A 2-D vector of f64: just what the path algebra needs, the twin of WGSL's `vec2`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Vec2 {
    /// x component.
    pub x: f64,
    /// y component.
    pub y: f64,
}

impl Vec2 {
    /// The zero vector.
    pub const ZERO: Vec2 = Vec2 { x: 0.0, y: 0.0 };

    /// A vector from its components.
    pub const fn new(x: f64, y: f64) -> Vec2 {
        Vec2 { x, y }
    }
}

/// Dot product (WGSL `dot2`: written out the same way, not the builtin, whose order of
/// operations is the driver's).
pub fn dot(a: Vec2, b: Vec2) -> f64 {
    a.x * b.x + a.y * b.y
}

/// Euclidean length, `sqrt(dot(a, a))` (WGSL: the same function, not the `length` builtin).
pub fn norm(a: Vec2) -> f64 {
    dot(a, a).sqrt()
}

/// The 2-D cross product `a.x b.y − a.y b.x`: `|a|` times the signed distance of `b` from
/// the line along `a` (WGSL: the same function).
pub fn perp_dot(a: Vec2, b: Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// The 1-norm `|a.x| + |a.y|`, an upper bound of [`norm`] without a square root (WGSL: the
/// same function).
pub fn norm1(a: Vec2) -> f64 {
    a.x.abs() + a.y.abs()
}

impl Add for Vec2 {
    type Output = Vec2;
    fn add(self, o: Vec2) -> Vec2 {
        Vec2::new(self.x + o.x, self.y + o.y)
    }
}

impl Sub for Vec2 {
    type Output = Vec2;
    fn sub(self, o: Vec2) -> Vec2 {
        Vec2::new(self.x - o.x, self.y - o.y)
    }
}

impl Neg for Vec2 {
    type Output = Vec2;
    fn neg(self) -> Vec2 {
        Vec2::new(-self.x, -self.y)
    }
}

impl Mul<Vec2> for f64 {
    type Output = Vec2;
    fn mul(self, v: Vec2) -> Vec2 {
        Vec2::new(self * v.x, self * v.y)
    }
}
