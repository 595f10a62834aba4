//! Which structure should a scene get? A structure costs its build once and its traversal
//! for every ray, so tracing `N` rays takes `build + N · trace` in all: lines in `N` whose
//! lower envelope says, for every number of rays, which structure is fastest overall, from a
//! quick middle split for a few thousand rays to a swept SAH for a film. The crossovers are
//! where the envelope changes hands.

/// The numbers of rays the break-even is reported at: 10³ to 10⁹.
pub const REPORTED_RAYS: [f64; 7] = [1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9];

/// One structure's measured costs.
#[derive(Clone, Debug, PartialEq)]
pub struct Contender {
    /// Its name.
    pub name: String,
    /// The build's time, milliseconds.
    pub build_ms: f64,
    /// One ray's traversal, milliseconds.
    pub ms_per_ray: f64,
}

impl Contender {
    /// The total time for `rays` rays, milliseconds.
    pub fn total_ms(&self, rays: f64) -> f64 {
        self.build_ms + rays * self.ms_per_ray
    }
}

/// The fastest structure for one number of rays.
#[derive(Clone, Debug, PartialEq)]
pub struct Fastest {
    /// How many rays.
    pub rays: f64,
    /// The fastest contender's index.
    pub fastest: usize,
    /// Its total time, milliseconds.
    pub total_ms: f64,
    /// The next fastest's index and how many times slower it is (`None` with one contender).
    pub runner_up: Option<(usize, f64)>,
}

/// Where the fastest structure changes: from `from` to `to` at `rays` rays.
#[derive(Clone, Debug, PartialEq)]
pub struct Crossover {
    /// The number of rays (not a whole number: where the two lines cross).
    pub rays: f64,
    /// The contender fastest below it.
    pub from: usize,
    /// The contender fastest above it.
    pub to: usize,
}

/// The break-even as reported: the fastest contender at each of [`REPORTED_RAYS`], and the
/// crossovers between the first and the last.
pub fn reported(contenders: &[Contender]) -> (Vec<Fastest>, Vec<Crossover>) {
    (
        fastest_at(contenders, &REPORTED_RAYS),
        crossovers(
            contenders,
            REPORTED_RAYS[0],
            REPORTED_RAYS[REPORTED_RAYS.len() - 1],
        ),
    )
}

/// The contenders a plot of total time against rays draws, in order: those fastest at some
/// reported number of rays, both sides of every crossover, and the lecture's rules (a BVH
/// split in the middle, at the median, by the swept SAH, and the kD SAH tree) to compare
/// with.
pub fn plotted(
    contenders: &[Contender],
    fastest: &[Fastest],
    crossings: &[Crossover],
) -> Vec<usize> {
    let mut shown: Vec<usize> = fastest.iter().map(|row| row.fastest).collect();
    shown.extend(
        crossings
            .iter()
            .flat_map(|crossing| [crossing.from, crossing.to]),
    );
    for name in ["bvh:middle", "bvh:median", "bvh:sah-sweep", "kd:sah"] {
        if let Some(index) = contenders.iter().position(|c| c.name == name) {
            shown.push(index);
        }
    }
    shown.sort_unstable();
    shown.dedup();
    shown
}

/// The fastest contender at each of `rays` (ties to the lower index), with the runner-up.
pub fn fastest_at(contenders: &[Contender], rays: &[f64]) -> Vec<Fastest> {
    rays.iter()
        .filter_map(|&count| {
            let mut order: Vec<usize> = (0..contenders.len()).collect();
            order.sort_by(|&a, &b| {
                contenders[a]
                    .total_ms(count)
                    .total_cmp(&contenders[b].total_ms(count))
                    .then(a.cmp(&b))
            });
            let fastest = *order.first()?;
            let total_ms = contenders[fastest].total_ms(count);
            let runner_up = order.get(1).map(|&next| {
                let ratio = if total_ms > 0.0 {
                    contenders[next].total_ms(count) / total_ms
                } else {
                    f64::INFINITY
                };
                (next, ratio)
            });
            Some(Fastest {
                rays: count,
                fastest,
                total_ms,
                runner_up,
            })
        })
        .collect()
}

/// The crossovers of the lower envelope between `low` and `high` rays, in order.
pub fn crossovers(contenders: &[Contender], low: f64, high: f64) -> Vec<Crossover> {
    let Some(first) = fastest_at(contenders, &[low]).first().map(|f| f.fastest) else {
        return Vec::new();
    };
    let mut found = Vec::new();
    let (mut current, mut at) = (first, low);
    loop {
        // The first line below the current one after `at`: it must trace faster.
        let line = &contenders[current];
        let next = contenders
            .iter()
            .enumerate()
            .filter(|(index, other)| *index != current && other.ms_per_ray < line.ms_per_ray)
            .map(|(index, other)| {
                let rays = (other.build_ms - line.build_ms) / (line.ms_per_ray - other.ms_per_ray);
                (index, rays)
            })
            .filter(|&(_, rays)| rays > at && rays <= high)
            .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
        let Some((index, rays)) = next else { break };
        found.push(Crossover {
            rays,
            from: current,
            to: index,
        });
        current = index;
        at = rays;
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    fn contender(name: &str, build_ms: f64, ms_per_ray: f64) -> Contender {
        Contender {
            name: name.into(),
            build_ms,
            ms_per_ray,
        }
    }

    #[test]
    fn a_quick_build_wins_few_rays_and_a_good_tree_many() {
        // quick: 10 ms + 1 µs a ray; good: 100 ms + 0.5 µs; best: 1000 ms + 0.4 µs.
        // quick = good at 90 / 0.0005 = 180,000 rays; good = best at 900 / 0.0001 = 9e6.
        let contenders = [
            contender("quick", 10.0, 1e-3),
            contender("good", 100.0, 5e-4),
            contender("best", 1000.0, 4e-4),
        ];
        let rows = fastest_at(&contenders, &[1e3, 1e6, 1e8]);
        assert_eq!(
            rows.iter().map(|row| row.fastest).collect::<Vec<_>>(),
            [0, 1, 2]
        );
        assert_eq!(rows[0].total_ms, 11.0);
        // At a million rays: good 600 ms, quick 1010 ms.
        let (next, ratio) = rows[1].runner_up.unwrap();
        assert_eq!(next, 0);
        assert!((ratio - 1010.0 / 600.0).abs() < 1e-12);
        let crossings = crossovers(&contenders, 1e3, 1e9);
        assert_eq!(crossings.len(), 2);
        assert!((crossings[0].rays - 180_000.0).abs() < 1e-6);
        assert_eq!((crossings[0].from, crossings[0].to), (0, 1));
        assert!((crossings[1].rays - 9e6).abs() < 1e-3);
        assert_eq!((crossings[1].from, crossings[1].to), (1, 2));
    }

    #[test]
    fn a_tree_that_is_slower_to_build_and_to_trace_never_wins() {
        let contenders = [
            contender("fine", 10.0, 1e-3),
            contender("worse", 20.0, 2e-3),
        ];
        assert!(crossovers(&contenders, 1e3, 1e9).is_empty());
        assert!(
            fastest_at(&contenders, &[1e3, 1e9])
                .iter()
                .all(|row| row.fastest == 0)
        );
        assert!(fastest_at(&[], &[1e3]).is_empty());
    }
}
