// Ball–pocket detection (spec §4.6): the moment the ball's centre enters the pocket
// circle, "the point of no return". The depth plays no part. WGSL twin of
// src/query/ball_pocket.rs.

// τ until a translating ball's centre enters the circle of radius r_p (not r_p ± R)
// about the pocket's centre (or, for a centre a kiss left inside it, leaves it: pooltool's
// quartic does not ask which way), or NEVER (non-translating balls too).
fn ball_pocket_time(b: BallState, pocket: Pocket, p: BallParams) -> real {
    if !ball_translating(b) {
        return NEVER;
    }
    let path = trajectory(b, p);
    let center = real2(pocket.center.x, pocket.center.y);
    return circle_crossing(path, center, pocket.radius);
}
