// Ball–pocket resolution, pooltool's `canonical` model (spec §5.5;
// `physics/resolve/ball_pocket/__init__.py`): the ball drops to the pocket's centre at
// z = −depth, at rest, labelled pocketed. No rattle, no depth physics (Q15). WGSL twin of
// src/resolve/ball_pocket.rs.
//
// Needs (before it): the precision prelude, model/ball.wgsl, model/ball_state.wgsl,
// model/table.wgsl.

// The ball after falling into `pocket`.
fn resolve_pocket(b: BallState, pocket: Pocket) -> BallState {
    return BallState(
        real3(pocket.center.x, pocket.center.y, -pocket.depth),
        real3(0.0, 0.0, 0.0),
        real3(0.0, 0.0, 0.0),
        STATE_POCKETED,
        b.t,
    );
}
