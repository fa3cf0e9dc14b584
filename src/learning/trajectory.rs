//! One episode as a learner records it: rewards with their times, choices with theirs.

use super::KeyId;

/// The record of one plan level during one episode, in executor steps.
///
/// Reward reported at a marking change covers the interval that began at the
/// previous change; its discount is gamma^(start of interval - time of the
/// visit), the semi-Markov convention of the reference library (reward summed
/// over an interval, the next value discounted by gamma^elapsed).
#[derive(Debug, Default, Clone)]
pub struct Trajectory {
    time: u32,
    rewards: Vec<(u32, f64)>,
    visits: Vec<(KeyId, u32)>,
    pending: Option<KeyId>,
    suffix: Vec<f64>,
}

impl Trajectory {
    /// Forgets the episode.
    pub(crate) fn clear(&mut self) {
        self.time = 0;
        self.rewards.clear();
        self.visits.clear();
        self.pending = None;
    }

    /// A choice entered afterstate `id`; its time is fixed by the marking change that follows.
    pub fn choose(&mut self, id: KeyId) {
        self.pending = Some(id);
    }

    /// A marking change after `elapsed` steps that collected `reward`.
    pub(crate) fn advance(&mut self, reward: f64, elapsed: u32) {
        if reward != 0.0 {
            self.rewards.push((self.time, reward));
        }
        self.time += elapsed;
        if let Some(id) = self.pending.take()
            && !self.visits.iter().any(|(v, _)| *v == id)
        {
            self.visits.push((id, self.time));
        }
    }

    /// Records a first visit of `id` now (for learners valuing every marking).
    pub(crate) fn visit(&mut self, id: KeyId) {
        if !self.visits.iter().any(|(v, _)| *v == id) {
            self.visits.push((id, self.time));
        }
    }

    /// Steps elapsed since the episode began.
    pub fn time(&self) -> u32 {
        self.time
    }

    /// First visits of chosen afterstates, in order, with their times.
    pub fn visits(&self) -> &[(KeyId, u32)] {
        &self.visits
    }

    /// The discounted return from time 0.
    pub(crate) fn total_return(&mut self, gamma: f64) -> f64 {
        self.return_from(gamma, 0)
    }

    /// Fills `out` with (afterstate, discounted return from its first visit): R_post-o.
    pub(crate) fn first_visit_returns(&mut self, gamma: f64, out: &mut Vec<(KeyId, f64)>) {
        out.clear();
        self.build_suffix(gamma);
        for i in 0..self.visits.len() {
            let (id, t) = self.visits[i];
            out.push((id, self.suffix_from(gamma, t)));
        }
    }

    fn return_from(&mut self, gamma: f64, t: u32) -> f64 {
        self.build_suffix(gamma);
        self.suffix_from(gamma, t)
    }

    fn build_suffix(&mut self, gamma: f64) {
        self.suffix.clear();
        self.suffix.resize(self.rewards.len(), 0.0);
        let mut next = 0.0;
        let mut next_time = None;
        for i in (0..self.rewards.len()).rev() {
            let (t, r) = self.rewards[i];
            let carried = match next_time {
                Some(nt) => next * discount(gamma, nt - t),
                None => 0.0,
            };
            next = r + carried;
            next_time = Some(t);
            self.suffix[i] = next;
        }
    }

    fn suffix_from(&self, gamma: f64, t: u32) -> f64 {
        let j = self.rewards.partition_point(|(s, _)| *s < t);
        match self.rewards.get(j) {
            Some((s, _)) => self.suffix[j] * discount(gamma, s - t),
            None => 0.0,
        }
    }
}

/// gamma^steps (1 when gamma is 1).
#[inline]
pub fn discount(gamma: f64, steps: u32) -> f64 {
    if gamma == 1.0 { 1.0 } else { gamma.powi(steps as i32) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn returns_are_discounted_from_each_first_visit() {
        let mut t = Trajectory::default();
        t.choose(7);
        t.advance(0.0, 1); // choice at time 1
        t.advance(2.0, 3); // reward 2 over [1, 4)
        t.choose(8);
        t.advance(1.0, 1); // reward 1 over [4, 5), choice at 5
        t.choose(7); // revisit: not a first visit
        t.advance(0.0, 1);
        t.advance(4.0, 2); // reward 4 over [6, 8)
        let gamma: f64 = 0.5;
        let mut out = Vec::new();
        t.first_visit_returns(gamma, &mut out);
        let r7 = 2.0 + gamma.powi(3) * 1.0 + gamma.powi(5) * 4.0;
        let r8 = gamma.powi(1) * 4.0;
        assert_eq!(out.len(), 2);
        assert!((out[0].1 - r7).abs() < 1e-12 && out[0].0 == 7);
        assert!((out[1].1 - r8).abs() < 1e-12 && out[1].0 == 8);
        assert!((t.total_return(1.0) - 7.0).abs() < 1e-12);
        assert_eq!(t.time(), 8);
    }
}
