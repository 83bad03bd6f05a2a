// 3-D vectors: WGSL's own vec3 (`real3`) with the helpers the physics needs. WGSL twin of
// src/model/vec3.rs.
//
// Frame (spec §0): x along the table's short side, y along the long side, z up; the cloth
// is z = 0.

// Dot product v·o, written out (the builtin's order of operations is the driver's).
fn dot3(v: real3, o: real3) -> real {
    return v.x * o.x + v.y * o.y + v.z * o.z;
}

// Cross product v × o, written out (as the builtin's, whose operations are the driver's).
fn cross3(v: real3, o: real3) -> real3 {
    return real3(v.y * o.z - v.z * o.y, v.z * o.x - v.x * o.z, v.x * o.y - v.y * o.x);
}

// Euclidean length sqrt(v·v) (not the `length` builtin).
fn norm3(v: real3) -> real {
    return sqrt(dot3(v, v));
}

// v/|v|; the zero vector stays zero.
fn unit3(v: real3) -> real3 {
    let n = norm3(v);
    if n > 0.0 {
        return v * (1.0 / n);
    }
    return real3(0.0, 0.0, 0.0);
}

// The horizontal part (x, y, 0).
fn xy3(v: real3) -> real3 {
    return real3(v.x, v.y, 0.0);
}

// Rotated counter-clockwise about z by `angle` radians (Rz(angle)·v, spec §0).
fn rotate_z(v: real3, angle: real) -> real3 {
    return rotate_z_cs(v, real_cos(angle), real_sin(angle));
}

// Rotated counter-clockwise about z by the angle whose cosine and sine are `c`, `s`.
fn rotate_z_cs(v: real3, c: real, s: real) -> real3 {
    return real3(c * v.x - s * v.y, s * v.x + c * v.y, v.z);
}
