// 2-D vectors: WGSL's own vec2 (`real2`) with the helpers the path algebra needs. WGSL
// twin of src/model/vec2.rs.

// Dot product a.x b.x + a.y b.y, written out (the builtin's order of operations is the
// driver's).
fn dot2(a: real2, b: real2) -> real {
    return a.x * b.x + a.y * b.y;
}

// Euclidean length, sqrt(dot2(a, a)) (not the `length` builtin).
fn norm(a: real2) -> real {
    return sqrt(dot2(a, a));
}

// The 2-D cross product a.x b.y − a.y b.x: |a| times the signed distance of b from the
// line along a.
fn perp_dot(a: real2, b: real2) -> real {
    return a.x * b.y - a.y * b.x;
}

// The 1-norm |a.x| + |a.y|, an upper bound of norm without a square root.
fn norm1(a: real2) -> real {
    return abs(a.x) + abs(a.y);
}
