//! What the trade's rows say, in sentences each made from the numbers: how often each triangle
//! test is wrong, per row (a sum over rows would count f32, which has twice the rows, twice),
//! what f64 changes, and why on rays aimed at edges the fast test can trace slower than the
//! watertight one. The trade lab (lesson 16) and `accelviz-cli tradeoff` print the same.

use crate::format::{count, number};
use crate::outcome::Outcome;
use crate::trade::{Precision, Switches, TradeRow};

/// The rows' leaks per million rays, low to high, and how many rows.
fn leak_range(rows: &[&TradeRow]) -> Option<(f64, f64, usize)> {
    let rates: Vec<f64> = rows
        .iter()
        .map(|row| row.outcomes.per_million(Outcome::Leak))
        .collect();
    let low = rates.iter().copied().reduce(f64::min)?;
    let high = rates.iter().copied().reduce(f64::max)?;
    Some((low, high, rates.len()))
}

/// A range of rates per million in words: one figure where they are one.
fn rate_text((low, high, rows): (f64, f64, usize)) -> String {
    let (low, high) = (count(low.round() as usize), count(high.round() as usize));
    let rows = if rows == 1 {
        "1 row".to_owned()
    } else {
        format!("each of {rows} rows")
    };
    if low == high {
        format!("{low} a million ({rows})")
    } else {
        format!("{low} to {high} a million ({rows})")
    }
}

/// The sentences `rows` support, each from their numbers.
pub fn summary(rows: &[TradeRow]) -> Vec<String> {
    let mut said = Vec::new();
    // The watertight test: its errors over every row.
    let watertight: Vec<&TradeRow> = rows.iter().filter(|row| row.switches.watertight).collect();
    if !watertight.is_empty() {
        let errors: u64 = watertight
            .iter()
            .map(|row| {
                [Outcome::Leak, Outcome::FalseHit, Outcome::Wrong]
                    .iter()
                    .map(|&outcome| row.outcomes.count(outcome))
                    .sum::<u64>()
            })
            .sum();
        said.push(format!(
            "The watertight test: {} leaks, false hits or wrong answers in its {} rows.",
            count(errors as usize),
            watertight.len()
        ));
    }
    // The fast test's leaks, a rate per row in each precision.
    let fast = |precision: Precision| -> Vec<&TradeRow> {
        rows.iter()
            .filter(|row| !row.switches.watertight && row.switches.precision == precision)
            .collect()
    };
    let (f32_rows, f64_rows) = (fast(Precision::F32), fast(Precision::F64));
    if let (Some(in_f32), Some(in_f64)) = (leak_range(&f32_rows), leak_range(&f64_rows)) {
        said.push(format!(
            "The fast test leaks {} in f32 and {} in f64.",
            rate_text(in_f32),
            rate_text(in_f64)
        ));
        let leaks = |(_, high, _): (f64, f64, usize)| high > 0.0;
        if leaks(in_f32) && leaks(in_f64) {
            said.push("Rays aimed exactly at an edge or a vertex leak in either precision: f64 narrows the band where rounding decides, but a ray through the edge itself still falls between the two triangles' tests.".to_owned());
        }
    }
    // Where leaking rays make the fast test slower: clearly, beyond the rounds' ranges.
    let pair = rows.iter().filter_map(|fast| {
        let base = fast.switches == Switches::BASE;
        let watertight = rows.iter().find(|row| {
            row.structure == fast.structure
                && row.switches
                    == Switches {
                        watertight: true,
                        ..Switches::BASE
                    }
        })?;
        (base && fast.outcomes.count(Outcome::Leak) > 0).then_some((fast, watertight))
    });
    let slower: Vec<(&TradeRow, &TradeRow)> = pair
        .clone()
        .filter(|(fast, watertight)| fast.ms_per_ray_range.0 > watertight.ms_per_ray_range.1)
        .collect();
    if let Some((fast, watertight)) = slower.first() {
        said.push(format!(
            "On these rays the fast test traced clearly slower than the watertight one in {} of {} structures (near first, f32; {}: {} against {} Mrays/s): a ray that slips through an edge does not stop there but travels on to the far side of the mesh, entering {} nodes a ray against {}.",
            slower.len(),
            pair.count(),
            fast.structure.name(),
            number(fast.mrays_per_s),
            number(watertight.mrays_per_s),
            number(fast.nodes_per_ray),
            number(watertight.nodes_per_ray)
        ));
    }
    said
}
