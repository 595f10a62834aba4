//! What the commands share: their arguments (the trace switches, the build parameters, the
//! precision, the lists their help is written from) and the rays an argument names.

use accelviz_core::params::BuildParams;
use accelviz_core::{Order, TraceOptions, Vector3};
use accelviz_scene::Mesh;
use accelviz_scene::rays::{RayReader, RaySpec};
use anyhow::{Context, Result};
use clap::{Args, ValueEnum};

/// Traversal order.
#[derive(Clone, Copy, Debug, Default, ValueEnum, PartialEq, Eq)]
pub enum OrderArg {
    /// The child the ray enters first.
    #[default]
    NearFirst,
    /// Children in memory order.
    FileOrder,
}

/// Arithmetic precision: the core's, one for the whole project.
pub use accelviz_core::trade::Precision;

/// `--precision`'s values, parsed into the core's [`Precision`] (it knows nothing of clap).
pub(crate) fn precision_parser() -> impl clap::builder::TypedValueParser<Value = Precision> {
    use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
    PossibleValuesParser::new([
        PossibleValue::new("f32").help("32-bit floats (fast)"),
        PossibleValue::new("f64").help("64-bit floats (accurate)"),
    ])
    .map(|name| match name.as_str() {
        "f64" => Precision::F64,
        _ => Precision::F32,
    })
}

/// Switches shared by `query` and `bench`.
#[derive(Args, Debug, Clone, Copy)]
pub struct TraceArgs {
    /// Child order when the ray hits both children. Default: near-first for the closest
    /// hit, file-order for any hit (ordering buys an occlusion query nothing, as in Embree's).
    #[arg(long, value_enum)]
    pub(crate) order: Option<OrderArg>,
    /// Arithmetic precision of the structure, the triangles and the rays.
    #[arg(long, value_parser = precision_parser(), default_value = "f32")]
    pub(crate) precision: Precision,
    /// Watertight triangle test (Woop et al. 2013) and conservative box test (Ize 2013).
    #[arg(long)]
    pub(crate) robust: bool,
    /// kD-trees: test a primitive listed in several leaves once per ray (a mailbox).
    #[arg(long)]
    pub(crate) mailbox: bool,
    /// closest, or any (is anything in the way?). Default: any for shadow and ao rays,
    /// closest otherwise.
    #[arg(long, value_parser = accelviz_core::Query::parse)]
    pub(crate) query: Option<accelviz_core::Query>,
}

/// The build parameters shared by `query` and `bench`.
#[derive(Args, Debug, Clone, Copy)]
pub struct BuildArgs {
    /// Nodes with more primitives are always split (SAH builders may stop earlier).
    #[arg(long, default_value_t = BuildParams::default().max_leaf_size)]
    pub(crate) max_leaf_size: usize,
    /// SAH cost of visiting an interior node, C_trav.
    #[arg(long, default_value_t = BuildParams::default().cost.traversal_cost)]
    pub(crate) traversal_cost: f64,
    /// SAH cost of one ray/triangle test, C_isect.
    #[arg(long, default_value_t = BuildParams::default().cost.intersection_cost)]
    pub(crate) intersection_cost: f64,
    /// kD SAH: the share by which a cut leaving one side empty is made cheaper (0 to 1).
    #[arg(long, default_value_t = BuildParams::default().cost.empty_bonus)]
    pub(crate) empty_bonus: f64,
}

impl BuildArgs {
    /// The core's parameters, checked.
    pub fn params(&self) -> Result<BuildParams> {
        let costs = [self.traversal_cost, self.intersection_cost];
        if costs.iter().any(|cost| !cost.is_finite() || *cost <= 0.0) {
            anyhow::bail!("--traversal-cost and --intersection-cost must be positive numbers");
        }
        if !(0.0..=1.0).contains(&self.empty_bonus) {
            anyhow::bail!("--empty-bonus must be a number from 0 to 1");
        }
        if self.max_leaf_size == 0 {
            anyhow::bail!("--max-leaf-size must be at least 1");
        }
        Ok(BuildParams {
            max_leaf_size: self.max_leaf_size,
            cost: accelviz_core::SahCost {
                traversal_cost: self.traversal_cost,
                intersection_cost: self.intersection_cost,
                empty_bonus: self.empty_bonus,
            },
            ..BuildParams::default()
        })
    }
}

impl Default for BuildArgs {
    fn default() -> Self {
        let params = BuildParams::default();
        Self {
            max_leaf_size: params.max_leaf_size,
            traversal_cost: params.cost.traversal_cost,
            intersection_cost: params.cost.intersection_cost,
            empty_bonus: params.cost.empty_bonus,
        }
    }
}

impl TraceArgs {
    /// The core's options, with `--query` or else the closest hit.
    pub fn options(&self) -> TraceOptions {
        self.options_for(None)
    }

    /// The core's options for rays of `kind`: `--query`, or else the query such rays ask.
    pub fn options_for(&self, kind: Option<accelviz_scene::rays::RayKind>) -> TraceOptions {
        let query = self
            .query
            .or(kind.map(|kind| kind.default_query()))
            .unwrap_or_default();
        TraceOptions {
            query,
            order: match self.order {
                Some(OrderArg::NearFirst) => Order::NearFirst,
                Some(OrderArg::FileOrder) => Order::FileOrder,
                None => query.default_order(),
            },
            mailboxing: self.mailbox,
            ..TraceOptions::default()
        }
        .with_robust(self.robust)
    }
}

/// `--mesh`'s help: every built-in mesh, from the scene crate's table.
pub fn mesh_help() -> String {
    let names: Vec<&str> = accelviz_scene::builtin::BUILTINS
        .iter()
        .map(|builtin| builtin.name)
        .collect();
    format!(
        "The mesh: an OBJ file, or builtin:NAME, NAME one of {}",
        names.join(", ")
    )
}

/// Parses `--repeat`: at least one round.
pub fn parse_rounds(text: &str) -> Result<usize, String> {
    match text.parse::<usize>() {
        Ok(0) => Err("at least one round is needed".to_owned()),
        Ok(rounds) => Ok(rounds),
        Err(_) => Err(format!("'{text}' is not a number of rounds")),
    }
}

/// `--accel`'s help (`what` names it): every structure of the catalogue.
pub fn structure_help(what: &str) -> String {
    format!(
        "{what}: brute (every triangle), or {}; a BVH of 4 or 8 children as bvh4:… or bvh8:… (bvh8:sah-binned)",
        accelviz_core::structure::valid_names()
    )
}

/// Converts rays to the chosen precision, naming the line of any that cannot be.
pub fn convert_rays<V: Vector3>(
    rays: &[RaySpec],
    source: &str,
) -> Result<Vec<accelviz_core::Ray<V>>> {
    rays.iter()
        .map(|spec| {
            spec.to_ray::<V>()
                .with_context(|| format!("{source}:{}: bad ray", spec.line))
        })
        .collect()
}

/// The rays of `source` for `mesh`, in `V`'s precision. A ray file is read a line at a time,
/// each ray kept only as `V` has it (32 bytes in f32: 10 million rays in 320 MB, where the
/// file's text and its rays in f64 took 2 GB); generated rays are made, then converted.
pub fn rays_of<V: Vector3>(
    source: &accelviz_scene::rays::RaySource,
    mesh: &Mesh,
) -> Result<Vec<accelviz_core::Ray<V>>> {
    match source {
        accelviz_scene::rays::RaySource::File(path) => {
            let mut rays = Vec::new();
            for spec in RayReader::open(path)? {
                let spec = spec?;
                rays.push(
                    spec.to_ray::<V>()
                        .with_context(|| format!("{path}:{}: bad ray", spec.line))?,
                );
            }
            Ok(rays)
        }
        _ => convert_rays(&source.rays(mesh)?, &source.label()),
    }
}
