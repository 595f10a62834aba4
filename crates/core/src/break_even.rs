//! Which structure should a scene get? A structure costs its build once and its traversal
//! for every ray, so tracing `N` rays takes `build + N · trace` in all: lines in `N` whose
//! lower envelope says, for every number of rays, which structure is fastest overall, from a
//! quick middle split for a few thousand rays to a swept SAH for a film. The crossovers are
//! where the envelope changes hands.
//!
//! Every time is measured over rounds, and the rounds spread. A structure's total for `N`
//! rays lies between its fastest rounds' total and its slowest's; two structures whose
//! totals' ranges overlap are not shown to differ, so the break-even names a winner only where
//! its range lies below every other's, and a crossover only where the ranges part on both
//! sides of it. A machine under load, or a browser's frame loop, spreads the rounds by ±50 %
//! and more: then the verdict says that nothing is clear, rather than rank the noise.

/// The numbers of rays the break-even is reported at: 10³ to 10⁹.
pub const REPORTED_RAYS: [f64; 7] = [1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9];

/// One structure's measured costs: the medians of the rounds, and the fastest and the
/// slowest round.
#[derive(Clone, Debug, PartialEq)]
pub struct Contender {
    /// Its name.
    pub name: String,
    /// The build's time, milliseconds (the median round).
    pub build_ms: f64,
    /// One ray's traversal, milliseconds (the median round).
    pub ms_per_ray: f64,
    /// The build's fastest and slowest rounds, milliseconds.
    pub build_range_ms: (f64, f64),
    /// One ray's traversal in the fastest and the slowest round, milliseconds.
    pub ms_per_ray_range: (f64, f64),
}

impl Contender {
    /// A contender timed once (no spread): `build_ms` and `ms_per_ray` are its ranges' ends.
    pub fn exact(name: impl Into<String>, build_ms: f64, ms_per_ray: f64) -> Self {
        Self {
            name: name.into(),
            build_ms,
            ms_per_ray,
            build_range_ms: (build_ms, build_ms),
            ms_per_ray_range: (ms_per_ray, ms_per_ray),
        }
    }

    /// The total time for `rays` rays, milliseconds (the medians').
    pub fn total_ms(&self, rays: f64) -> f64 {
        self.build_ms + rays * self.ms_per_ray
    }

    /// The total for `rays` rays from the fastest rounds to the slowest, milliseconds.
    pub fn total_range_ms(&self, rays: f64) -> (f64, f64) {
        (
            self.build_range_ms.0 + rays * self.ms_per_ray_range.0,
            self.build_range_ms.1 + rays * self.ms_per_ray_range.1,
        )
    }

    /// Whether it is faster than `other` for `rays` rays beyond the rounds' spread: its
    /// slowest total below the other's fastest.
    pub fn clearly_faster_than(&self, other: &Contender, rays: f64) -> bool {
        self.total_range_ms(rays).1 < other.total_range_ms(rays).0
    }
}

/// The fastest structure for one number of rays.
#[derive(Clone, Debug, PartialEq)]
pub struct Fastest {
    /// How many rays.
    pub rays: f64,
    /// The fastest contender's index (by the medians).
    pub fastest: usize,
    /// Its total time, milliseconds.
    pub total_ms: f64,
    /// The next fastest's index and how many times slower it is (`None` with one contender).
    pub runner_up: Option<(usize, f64)>,
    /// The other contenders not clearly slower (their ranges overlap the fastest's), by
    /// their medians: empty when the fastest is a clear winner.
    pub within_spread: Vec<usize>,
}

impl Fastest {
    /// Whether the fastest beats every other contender beyond the rounds' spread.
    pub fn is_clear(&self) -> bool {
        self.within_spread.is_empty()
    }
}

/// Where the fastest structure changes: from `from` to `to` at `rays` rays.
#[derive(Clone, Debug, PartialEq)]
pub struct Crossover {
    /// The number of rays (not a whole number: where the two medians' lines cross).
    pub rays: f64,
    /// The contender fastest below it.
    pub from: usize,
    /// The contender fastest above it.
    pub to: usize,
    /// Where the change lies beyond the rounds' spread, if it does: `from` is clearly faster
    /// than `to` up to the first number of rays, `to` clearly faster from the second on.
    /// `None`: within the range reported the two are not shown to differ on one side.
    pub clear_between: Option<(f64, f64)>,
}

/// The break-even as reported: which structure is fastest at each of [`REPORTED_RAYS`] and
/// where that changes, each said only as far as the rounds' spread allows. What the trade
/// lab (lesson 16) and `accelviz-cli tradeoff` both report.
#[derive(Clone, Debug, PartialEq)]
pub struct BreakEven {
    /// The structures compared.
    pub contenders: Vec<Contender>,
    /// The fastest at each of [`REPORTED_RAYS`].
    pub fastest: Vec<Fastest>,
    /// The crossovers of the medians' lower envelope between the first and the last.
    pub crossovers: Vec<Crossover>,
    /// How many rounds each contender was timed in: with one, the rounds' spread is unknown
    /// and nothing is clear.
    pub rounds: usize,
}

impl BreakEven {
    /// The break-even of `contenders`, each timed in `rounds` rounds. With fewer than two the
    /// ranges say nothing of the spread: no winner and no crossover is clear.
    pub fn of(contenders: Vec<Contender>, rounds: usize) -> Self {
        let mut fastest = fastest_at(&contenders, &REPORTED_RAYS);
        let mut crossovers = crossovers(
            &contenders,
            REPORTED_RAYS[0],
            REPORTED_RAYS[REPORTED_RAYS.len() - 1],
        );
        if rounds < 2 {
            for row in &mut fastest {
                row.within_spread = (0..contenders.len())
                    .filter(|&index| index != row.fastest)
                    .collect();
            }
            for crossing in &mut crossovers {
                crossing.clear_between = None;
            }
        }
        Self {
            contenders,
            fastest,
            crossovers,
            rounds,
        }
    }

    /// A contender's name.
    pub fn name(&self, index: usize) -> &str {
        &self.contenders[index].name
    }

    /// The verdict in sentences, each from the numbers: the clear crossovers (where the
    /// change lies), and what the spread leaves open.
    pub fn verdict(&self) -> Vec<String> {
        if self.rounds < 2 {
            return vec!["Timed in one round, the rounds' spread is unknown: no structure is named fastest. Measure with more rounds.".to_owned()];
        }
        let mut said = Vec::new();
        for crossing in &self.crossovers {
            if let Some((low, high)) = crossing.clear_between {
                let (from, to) = (self.name(crossing.from), self.name(crossing.to));
                said.push(if rays_text(low) == rays_text(high) {
                    format!("{from} gives way to {to} at about {} rays.", rays_text(low))
                } else {
                    format!(
                        "{from} gives way to {to} between {} and {} rays (the medians cross at {}).",
                        rays_text(low),
                        rays_text(high),
                        rays_text(crossing.rays)
                    )
                });
            }
        }
        let unclear: Vec<&Fastest> = self.fastest.iter().filter(|f| !f.is_clear()).collect();
        if let (Some(first), Some(last)) = (unclear.first(), unclear.last()) {
            let mut names: Vec<usize> = unclear
                .iter()
                .flat_map(|f| std::iter::once(f.fastest).chain(f.within_spread.iter().copied()))
                .collect();
            names.sort_unstable();
            names.dedup();
            let listed: Vec<&str> = names.iter().map(|&index| self.name(index)).collect();
            let at = if first.rays == last.rays {
                format!("At {} rays", rays_text(first.rays))
            } else {
                format!(
                    "From {} to {} rays",
                    rays_text(first.rays),
                    rays_text(last.rays)
                )
            };
            said.push(format!(
                "{at} no structure is clearly fastest: the rounds' ranges of {} overlap. Measure with more rays or rounds, on a quieter machine, to tell them apart.",
                join_names(&listed)
            ));
        }
        if self.crossovers.iter().any(|c| c.clear_between.is_none()) && said.is_empty() {
            said.push(
                "The fastest changes hands within the rounds' spread: no clear crossover.".into(),
            );
        }
        said
    }
}

/// A number of rays in words: whole below ten thousand, else with an exponent.
pub fn rays_text(rays: f64) -> String {
    if rays < 1e4 {
        format!("{rays:.0}")
    } else {
        let exponent = rays.log10().floor();
        let mantissa = rays / 10f64.powf(exponent);
        format!("{mantissa:.1}e{exponent:.0}")
    }
}

/// Names joined with commas and a last "and".
fn join_names(names: &[&str]) -> String {
    match names {
        [] => String::new(),
        [one] => (*one).to_owned(),
        [rest @ .., last] => format!("{} and {last}", rest.join(", ")),
    }
}

/// The contenders a plot of total time against rays draws, in order: those fastest at some
/// reported number of rays, both sides of every crossover, and the lecture's rules (a BVH
/// split in the middle, at the median, by the swept SAH, and the kD SAH tree) to compare
/// with.
pub fn plotted(break_even: &BreakEven) -> Vec<usize> {
    let contenders = &break_even.contenders;
    let mut shown: Vec<usize> = break_even.fastest.iter().map(|row| row.fastest).collect();
    shown.extend(
        break_even
            .crossovers
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

/// The fastest contender at each of `rays` (ties to the lower index), with the runner-up and
/// the contenders within the spread.
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
            let within_spread = order[1..]
                .iter()
                .copied()
                .filter(|&other| {
                    !contenders[fastest].clearly_faster_than(&contenders[other], count)
                })
                .collect();
            Some(Fastest {
                rays: count,
                fastest,
                total_ms,
                runner_up,
                within_spread,
            })
        })
        .collect()
}

/// The crossovers of the medians' lower envelope between `low` and `high` rays, in order,
/// each with where it lies beyond the spread, if it does.
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
            clear_between: clear_between(&contenders[current], &contenders[index], low, high),
        });
        current = index;
        at = rays;
    }
    found
}

/// Where `from` stops being clearly faster than `to` and `to` starts being clearly faster
/// than `from`, if both happen between `low` and `high` rays. Each is a comparison of two
/// lines in `N` (one's slowest total against the other's fastest), so it holds on one side of
/// the point where they meet.
fn clear_between(from: &Contender, to: &Contender, low: f64, high: f64) -> Option<(f64, f64)> {
    if !(from.clearly_faster_than(to, low) && to.clearly_faster_than(from, high)) {
        return None;
    }
    // Where `from`'s slowest line meets `to`'s fastest, and `to`'s slowest meets `from`'s
    // fastest; each slope difference is positive, or the comparison could not change.
    let meet = |a: &Contender, b: &Contender| {
        let (build_a, build_b) = (a.build_range_ms.1, b.build_range_ms.0);
        let (slope_a, slope_b) = (a.ms_per_ray_range.1, b.ms_per_ray_range.0);
        (build_b - build_a) / (slope_a - slope_b)
    };
    let until = meet(from, to).clamp(low, high);
    let from_on = meet(to, from).clamp(low, high);
    Some((until.min(from_on), until.max(from_on)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn contender(name: &str, build_ms: f64, ms_per_ray: f64) -> Contender {
        Contender::exact(name, build_ms, ms_per_ray)
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

    /// A contender whose rounds spread by `spread` (a share) around its medians.
    fn spread(name: &str, build_ms: f64, ms_per_ray: f64, spread: f64) -> Contender {
        Contender {
            build_range_ms: (build_ms * (1.0 - spread), build_ms * (1.0 + spread)),
            ms_per_ray_range: (ms_per_ray * (1.0 - spread), ms_per_ray * (1.0 + spread)),
            ..Contender::exact(name, build_ms, ms_per_ray)
        }
    }

    #[test]
    fn overlapping_ranges_name_no_winner() {
        // Medians 5 % apart, rounds ±20 %: the medians' order is noise.
        let break_even = BreakEven::of(
            vec![
                spread("a", 1.0, 1.00e-3, 0.2),
                spread("b", 1.05, 1.05e-3, 0.2),
            ],
            3,
        );
        assert!(break_even.fastest.iter().all(|f| !f.is_clear()));
        assert!(
            break_even
                .fastest
                .iter()
                .all(|f| f.within_spread == [1 - f.fastest])
        );
        let verdict = break_even.verdict();
        assert_eq!(verdict.len(), 1, "{verdict:?}");
        assert!(
            verdict[0].contains("no structure is clearly fastest"),
            "{verdict:?}"
        );
        assert!(verdict[0].contains("a and b"), "{verdict:?}");
    }

    #[test]
    fn a_clear_crossover_says_where_it_lies() {
        // quick: 10 ms + 1 µs a ray, good: 100 ms + 0.5 µs, each ±5 %: their medians cross
        // at 180,000 rays; quick is clearly faster until (95 − 10.5) / (1.05e-3 − 0.475e-3)
        // ≈ 147,000 rays, good from (105 − 9.5) / (0.95e-3 − 0.525e-3) ≈ 224,700 on.
        let contenders = vec![
            spread("quick", 10.0, 1e-3, 0.05),
            spread("good", 100.0, 5e-4, 0.05),
        ];
        let break_even = BreakEven::of(contenders.clone(), 3);
        let crossing = &break_even.crossovers[0];
        let (low, high) = crossing.clear_between.expect("clear");
        assert!((low - 84.5 / 0.575e-3).abs() < 1e-6, "{low}");
        assert!((high - 95.5 / 0.425e-3).abs() < 1e-6, "{high}");
        assert!(low < crossing.rays && crossing.rays < high);
        let verdict = break_even.verdict();
        assert_eq!(
            verdict[0],
            "quick gives way to good between 1.5e5 and 2.2e5 rays (the medians cross at 1.8e5)."
        );
        // At 10⁵ rays quick's slowest total, 10.5 + 105 = 115.5 ms, lies below good's
        // fastest, 95 + 47.5 = 142.5 ms: a clear winner.
        assert!(break_even.fastest[2].is_clear());
        // Timed once, the same figures name nothing.
        let once = BreakEven::of(contenders, 1);
        assert!(once.fastest.iter().all(|f| !f.is_clear()));
        assert!(once.crossovers.iter().all(|c| c.clear_between.is_none()));
        assert_eq!(once.verdict().len(), 1);
        assert!(once.verdict()[0].contains("one round"));
    }
}
