//! `[ranks]`: how a run split across ranks cuts its domain (docs/distributed.md).

use serde::Deserialize;

/// `[ranks]`: read only by a run started as several ranks (`mpirun -np N sph run`); a run on
/// one rank ignores it. `sph run --decomposition` and `--rebalance` override it.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RanksFile {
    /// `"bisection"` (recursive coordinate bisection, the default) or `"slabs"` (along the
    /// domain's longest axis).
    pub decomposition: Option<DecompositionName>,
    /// Cut the domain again at a halo rebuild whose per-rank particle counts have an imbalance
    /// `max/mean − 1` above this (> 0; default 0.1), or `"never"`.
    pub rebalance: Option<RebalanceFile>,
}

/// `[ranks] decomposition`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DecompositionName {
    /// `distributed::Method::Bisection`.
    Bisection,
    /// `distributed::Method::Slabs`.
    Slabs,
}

/// `[ranks] rebalance`: a limit or a word.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(untagged)]
pub enum RebalanceFile {
    /// The imbalance limit (checked > 0 and finite).
    Limit(f64),
    /// `"never"` (any other word is an error naming the key).
    Word(String),
}
