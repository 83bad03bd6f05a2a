//! A batch as the input of the shot simulator ([`crate::simulate::simulate_batch`]).

use super::Batch;
use crate::error::SimError;
use crate::model::ball_state::BallState;
use crate::model::sim_params::Physics;
use crate::resolve::stick_ball::CueStrike;

impl Batch {
    /// The `input` of [`crate::simulate::simulate_batch`] for this batch: table `k`'s balls in ascending
    /// ball-id order ([`BallState::from_ball`] with radius `radius`) and `strikes[k]` (ball
    /// index within the table and strike; an empty `strikes` means no strike anywhere).
    ///
    /// ```
    /// use kisstime::{Ball, Batch};
    /// use kisstime::simulate::{BatchOptions, CueStrike, SimParams, Table, simulate_batch};
    ///
    /// let mut batch = Batch::new();
    /// batch.push_table(7, [(0, Ball::at_rest(0.635, 0.6)), (1, Ball::at_rest(0.635, 1.905))])?;
    /// let strikes = [Some((0, CueStrike { v0: 1.5, phi: 90.0, theta: 0.0, a: 0.0, b: 0.0 }))];
    /// let p = SimParams::default();
    /// let input = batch.sim_input(&strikes, p.ball.r);
    /// let mut options = BatchOptions::default();
    /// options.record_events = false;
    /// let stats = simulate_batch(&Table::nine_foot(), p, &options, batch.num_tables(), input, |chunk| {
    ///     // the object ball was hit: it moved
    ///     assert_ne!(chunk.get(0).unwrap().balls[1].r.y, 1.905);
    ///     Ok::<(), std::convert::Infallible>(())
    /// })
    /// .unwrap();
    /// assert!(stats.events > 3);
    /// # Ok::<(), kisstime::Error>(())
    /// ```
    pub fn sim_input<'a>(
        &'a self,
        strikes: &'a [Option<(usize, CueStrike)>],
        radius: f64,
    ) -> impl Fn(usize, &mut Vec<BallState>) -> Result<Option<(usize, CueStrike)>, SimError> + Sync + 'a
    {
        move |k, balls| {
            balls.clear();
            balls.extend(
                self.balls(k)
                    .iter()
                    .map(|b| BallState::from_ball(b, radius)),
            );
            Ok(strikes.get(k).copied().flatten())
        }
    }

    /// [`Batch::sim_input`] with each table's balls at its own radius (`physics.of(k)`'s
    /// R): the input of a batch with per-table physics.
    pub fn sim_input_for<'a>(
        &'a self,
        strikes: &'a [Option<(usize, CueStrike)>],
        physics: Physics<'a>,
    ) -> impl Fn(usize, &mut Vec<BallState>) -> Result<Option<(usize, CueStrike)>, SimError> + Sync + 'a
    {
        move |k, balls| {
            let radius = physics.of(k).ball.r;
            balls.clear();
            balls.extend(
                self.balls(k)
                    .iter()
                    .map(|b| BallState::from_ball(b, radius)),
            );
            Ok(strikes.get(k).copied().flatten())
        }
    }
}
