//! What the event loop reports: events (pooltool's `EventType`s with their agents) and how
//! a table's simulation ended.

/// pooltool's `EventType` values that a shot can produce (the two `none` events that
/// pooltool puts at the start and the end of a history are not reported).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum EventKind {
    /// The cue strikes the cue ball (agents: cue stick, ball).
    StickBall = 0,
    /// Two balls collide (agents: ball `i`, ball `j`, in pooltool's pair order).
    BallBall = 1,
    /// A ball hits a straight cushion segment (agents: ball, segment).
    BallLinearCushion = 2,
    /// A ball hits a circular cushion segment (agents: ball, jaw).
    BallCircularCushion = 3,
    /// A ball falls into a pocket (agents: ball, pocket).
    BallPocket = 4,
    /// Sliding → rolling.
    SlidingRolling = 5,
    /// Rolling → spinning.
    RollingSpinning = 6,
    /// Rolling → stationary.
    RollingStationary = 7,
    /// Spinning → stationary.
    SpinningStationary = 8,
}

impl EventKind {
    /// pooltool's `EventType` value (`stick_ball`, `ball_ball`, …), as the reference
    /// set's `events.csv` writes it.
    pub fn name(self) -> &'static str {
        match self {
            EventKind::StickBall => "stick_ball",
            EventKind::BallBall => "ball_ball",
            EventKind::BallLinearCushion => "ball_linear_cushion",
            EventKind::BallCircularCushion => "ball_circular_cushion",
            EventKind::BallPocket => "ball_pocket",
            EventKind::SlidingRolling => "sliding_rolling",
            EventKind::RollingSpinning => "rolling_spinning",
            EventKind::RollingStationary => "rolling_stationary",
            EventKind::SpinningStationary => "spinning_stationary",
        }
    }

    /// Whether the event is a motion transition of one ball.
    pub fn is_transition(self) -> bool {
        matches!(
            self,
            EventKind::SlidingRolling
                | EventKind::RollingSpinning
                | EventKind::RollingStationary
                | EventKind::SpinningStationary
        )
    }
}

/// "No second agent" in [`Event::other`].
pub const NO_AGENT: u32 = u32::MAX;

/// One event: its kind, its time, and its agents as indices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Event {
    /// What happened.
    pub kind: EventKind,
    /// When, in s since the strike.
    pub t: f64,
    /// The (first) ball's index.
    pub ball: u32,
    /// The second agent: the other ball (ball–ball), the segment, jaw or pocket index in
    /// the table's lists (cushions, pockets), or [`NO_AGENT`].
    pub other: u32,
}

/// Why a table's simulation stopped before every ball came to rest.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cut {
    /// The event cap was reached.
    MaxEvents,
    /// The next event lay past the simulated-time cap.
    MaxTime,
}

/// How one table's simulation ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outcome {
    /// Events reported (the strike included).
    pub n_events: usize,
    /// The time of the last event, s.
    pub t_end: f64,
    /// `None` when every ball came to rest (or was pocketed); else why the table was cut.
    pub cut: Option<Cut>,
}
