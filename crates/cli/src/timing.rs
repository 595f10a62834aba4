//! Honest timings on a shared machine: every configuration is timed once per round, the rounds
//! run one after another (so drift and a busy neighbour hit every configuration alike), and a
//! figure is the median of its rounds with the range it moved in.

use std::time::Instant;

/// The times of one configuration, one per round, in milliseconds.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Samples {
    millis: Vec<f64>,
}

impl Samples {
    /// Adds one round's time.
    pub fn push(&mut self, millis: f64) {
        self.millis.push(millis);
    }

    /// The median (the mean of the middle two for an even count; 0 without samples).
    pub fn median(&self) -> f64 {
        let mut sorted = self.millis.clone();
        sorted.sort_by(f64::total_cmp);
        match sorted.len() {
            0 => 0.0,
            n if n % 2 == 1 => sorted[n / 2],
            n => (sorted[n / 2 - 1] + sorted[n / 2]) / 2.0,
        }
    }

    /// The fastest round.
    pub fn min(&self) -> f64 {
        self.millis.iter().copied().fold(f64::INFINITY, f64::min)
    }

    /// The slowest round.
    pub fn max(&self) -> f64 {
        self.millis.iter().copied().fold(0.0, f64::max)
    }

    /// Half the range as a share of the median, in percent: `±spread` around the median
    /// covers every round. Two figures whose ranges overlap are not shown to differ.
    pub fn spread_percent(&self) -> f64 {
        let median = self.median();
        if median > 0.0 {
            (self.max() - self.min()) / 2.0 / median * 100.0
        } else {
            0.0
        }
    }
}

/// Runs `rounds` rounds; in each, calls `run(index)` for every configuration `0..count` and
/// times it. Odd rounds go through the configurations backwards, so none is always first
/// after a pause. Returns each configuration's samples.
pub fn interleaved(rounds: usize, count: usize, mut run: impl FnMut(usize)) -> Vec<Samples> {
    let mut samples = vec![Samples::default(); count];
    for round in 0..rounds.max(1) {
        for step in 0..count {
            let index = if round % 2 == 1 {
                count - 1 - step
            } else {
                step
            };
            let start = Instant::now();
            run(index);
            samples[index].push(start.elapsed().as_secs_f64() * 1e3);
        }
    }
    samples
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn medians_ranges_and_the_order_of_rounds() {
        let samples = Samples {
            millis: vec![12.0, 10.0, 30.0, 11.0],
        };
        assert_eq!(samples.median(), 11.5);
        assert_eq!((samples.min(), samples.max()), (10.0, 30.0));
        assert!((samples.spread_percent() - 10.0 / 11.5 * 100.0).abs() < 1e-9);
        let mut order = Vec::new();
        let timed = interleaved(3, 3, |index| order.push(index));
        assert_eq!(order, [0, 1, 2, 2, 1, 0, 0, 1, 2]);
        assert!(timed.iter().all(|samples| samples.millis.len() == 3));
    }
}
