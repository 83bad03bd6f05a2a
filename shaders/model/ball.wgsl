// A ball's state between events: the motion-state codes. WGSL twin of src/model/ball.rs
// (pooltool's codes; Rust: MotionState).

const STATE_STATIONARY: u32 = 0u;
const STATE_SPINNING: u32 = 1u;
const STATE_SLIDING: u32 = 2u;
const STATE_ROLLING: u32 = 3u;
const STATE_POCKETED: u32 = 4u;
