//! The trade's rows as bytes ([`crate::bytes`]): what a Web Worker that measured them sends
//! back to the page (the app's lesson 16 measures off the page's frame loop). Each row: its
//! structure's name, its switches, its build and trace numbers, its outcome counts and the
//! first ray of each outcome.

use glam::DVec3;

use crate::bytes::{ByteReader, ByteWriter, BytesError, REAL_BYTES};
use crate::outcome::OutcomeCounts;
use crate::query::Order;
use crate::ray::Ray;
use crate::structure::Structure;
use crate::trade::{Precision, Switches, TradeRow};

/// Marks the rows' bytes, and the version of their layout.
const ROWS_MAGIC: &[u8; 8] = b"accelvt2";

/// The fewest bytes a row takes (a name of no letters, no examples): a count of rows cannot
/// ask for more than the bytes hold.
const LEAST_ROW_BYTES: usize = 8 // the name's length
    + 3 // the switches
    + 5 * REAL_BYTES // the build's numbers
    + 1 + REAL_BYTES // the EPO
    + 8 // the bytes
    + 6 * REAL_BYTES // the trace's numbers
    + 6 * 8 // the outcome counts
    + 6; // each example's flag

impl TradeRow {
    /// `rows` as bytes.
    pub fn rows_to_bytes(rows: &[TradeRow]) -> Vec<u8> {
        let mut out = ByteWriter::new();
        out.raw(ROWS_MAGIC);
        out.usize(rows.len());
        for row in rows {
            row.write_bytes(&mut out);
        }
        out.into_bytes()
    }

    /// The rows [`TradeRow::rows_to_bytes`] wrote; cut short, padded or not rows at all: an
    /// error.
    pub fn rows_from_bytes(bytes: &[u8]) -> Result<Vec<TradeRow>, BytesError> {
        let mut input = ByteReader::new(bytes);
        if input.take(ROWS_MAGIC.len())? != ROWS_MAGIC {
            return Err(BytesError::Invalid("not the trade's rows".into()));
        }
        let rows = input.items(LEAST_ROW_BYTES, Self::read_bytes)?;
        input.finish()?;
        Ok(rows)
    }

    fn write_bytes(&self, out: &mut ByteWriter) {
        out.string(&self.structure.name());
        let Switches {
            order,
            precision,
            watertight,
        } = self.switches;
        out.u8(u8::from(order == Order::FileOrder));
        out.u8(u8::from(precision == Precision::F64));
        out.u8(u8::from(watertight));
        for value in [
            self.build_ms,
            self.build_spread_percent,
            self.build_range_ms.0,
            self.build_range_ms.1,
            self.sah_cost,
        ] {
            out.f64(value);
        }
        out.u8(u8::from(self.epo.is_some()));
        out.f64(self.epo.unwrap_or(0.0));
        out.usize(self.bytes);
        for value in [
            self.nodes_per_ray,
            self.primitives_per_ray,
            self.mrays_per_s,
            self.trace_spread_percent,
            self.ms_per_ray_range.0,
            self.ms_per_ray_range.1,
        ] {
            out.f64(value);
        }
        for count in self.outcomes.counts() {
            out.u64(count);
        }
        for example in &self.examples {
            out.u8(u8::from(example.is_some()));
            if let Some(ray) = example {
                out.vector(ray.origin);
                out.vector(ray.direction);
                out.f64(ray.t_min);
                out.f64(ray.t_max);
            }
        }
    }

    fn read_bytes(input: &mut ByteReader<'_>) -> Result<Self, BytesError> {
        let name = input.string()?;
        let structure =
            Structure::parse(&name).map_err(|error| BytesError::Invalid(error.to_string()))?;
        let flag = |input: &mut ByteReader<'_>| match input.u8()? {
            0 => Ok(false),
            1 => Ok(true),
            other => Err(BytesError::Unknown {
                what: "flag",
                tag: other.into(),
            }),
        };
        let switches = Switches {
            order: if flag(input)? {
                Order::FileOrder
            } else {
                Order::NearFirst
            },
            precision: if flag(input)? {
                Precision::F64
            } else {
                Precision::F32
            },
            watertight: flag(input)?,
        };
        let mut numbers = [0.0; 5];
        for value in &mut numbers {
            *value = input.f64()?;
        }
        let [
            build_ms,
            build_spread_percent,
            build_low,
            build_high,
            sah_cost,
        ] = numbers;
        let has_epo = flag(input)?;
        let epo = input.f64()?;
        let bytes = input.usize()?;
        let mut numbers = [0.0; 6];
        for value in &mut numbers {
            *value = input.f64()?;
        }
        let [nodes, primitives, mrays, spread, ray_low, ray_high] = numbers;
        let mut counts = [0; 6];
        for count in &mut counts {
            *count = input.u64()?;
        }
        let mut examples = [None; 6];
        for example in &mut examples {
            if flag(input)? {
                // As measured: not checked again.
                *example = Some(Ray {
                    origin: input.vector::<DVec3>()?,
                    direction: input.vector::<DVec3>()?,
                    t_min: input.f64()?,
                    t_max: input.f64()?,
                });
            }
        }
        Ok(TradeRow {
            structure,
            switches,
            build_ms,
            build_spread_percent,
            build_range_ms: (build_low, build_high),
            sah_cost,
            epo: has_epo.then_some(epo),
            bytes,
            nodes_per_ray: nodes,
            primitives_per_ray: primitives,
            mrays_per_s: mrays,
            trace_spread_percent: spread,
            ms_per_ray_range: (ray_low, ray_high),
            outcomes: OutcomeCounts::from_counts(counts),
            examples,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(name: &str, seed: f64) -> TradeRow {
        let ray = Ray {
            origin: DVec3::new(seed, -0.5, 2.0),
            direction: DVec3::new(0.1, 0.2, -1.0),
            t_min: 0.0,
            t_max: f64::INFINITY,
        };
        TradeRow {
            structure: Structure::parse(name).unwrap_or(Structure::KdSahPerfect),
            switches: Switches {
                order: Order::FileOrder,
                precision: Precision::F32,
                watertight: true,
            },
            build_ms: 1.5 * seed,
            build_spread_percent: 3.25,
            build_range_ms: (1.0, 2.0),
            sah_cost: 61.7,
            epo: (seed > 1.0).then_some(0.125),
            bytes: 123_456,
            nodes_per_ray: 17.5,
            primitives_per_ray: 4.25,
            mrays_per_s: 9.75,
            trace_spread_percent: 2.5,
            ms_per_ray_range: (1e-4, 2e-4),
            outcomes: OutcomeCounts::from_counts([5, 4, 3, 2, 1, 0]),
            examples: [Some(ray), None, Some(ray), None, None, Some(ray)],
        }
    }

    #[test]
    fn rows_come_back_the_same_and_broken_bytes_are_an_error() {
        let rows = vec![row("bvh:sah-binned:8", 1.0), row("kd:sah", 2.0)];
        let bytes = TradeRow::rows_to_bytes(&rows);
        assert_eq!(TradeRow::rows_from_bytes(&bytes), Ok(rows));
        for cut in [0, 7, 8, 16, bytes.len() / 2, bytes.len() - 1] {
            assert!(
                TradeRow::rows_from_bytes(&bytes[..cut]).is_err(),
                "cut at {cut}"
            );
        }
        let mut padded = bytes.clone();
        padded.push(0);
        assert_eq!(
            TradeRow::rows_from_bytes(&padded),
            Err(BytesError::TooMany(1))
        );
        assert_eq!(
            TradeRow::rows_from_bytes(&TradeRow::rows_to_bytes(&[])),
            Ok(Vec::new())
        );
    }
}
