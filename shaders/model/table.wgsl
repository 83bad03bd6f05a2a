// Table geometry (spec §6): straight cushion segments, circular cushion segments (the jaw
// tips) and pockets. WGSL twin of src/model/table.rs; the tables are built on the host
// and uploaded item by item, in pooltool's dict order (the detection order, which decides
// exact ties).

// A straight cushion segment: endpoints p1, p2 at the cushion height, the line
// lx·x + ly·y + l0 = 0 through them (spec §6.1), and which side is checked (direction
// 0 = SIDE1, where the line's value is < 0; 1 = SIDE2, > 0; 2 = both) (Rust:
// LinearCushion).
struct LinearCushion {
    p1: real3,
    p2: real3,
    direction: u32,
    lx: real,
    ly: real,
    l0: real,
}

// A circular cushion segment (a jaw tip): centre at the cushion height, radius (Rust:
// CircularCushion).
struct CircularCushion {
    center: real3,
    radius: real,
}

// A pocket: a circle on the cloth (centre z = 0) the ball centre must enter, and the
// depth a pocketed ball is stored at (spec §4.6, §5.5) (Rust: Pocket).
struct Pocket {
    center: real3,
    radius: real,
    depth: real,
}
