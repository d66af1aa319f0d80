//! `[ranks]`: how a run across ranks cuts its domain (`distributed::decomposition`).

use super::*;
use crate::distributed::{Method, Rebalance};
use crate::scene::RankSettings;
use crate::scene::schema::{DecompositionName, RanksFile, RebalanceFile};

/// The validated settings; `None` after reporting a problem.
pub(super) fn check_ranks(c: &mut Checker, file: &RanksFile) -> Option<RankSettings> {
    let path = KeyPath::key("ranks");
    let defaults = RankSettings::default();
    let method = match file.decomposition {
        None => defaults.method,
        Some(DecompositionName::Bisection) => Method::Bisection,
        Some(DecompositionName::Slabs) => Method::Slabs,
    };
    let rebalance = match &file.rebalance {
        None => defaults.rebalance,
        Some(RebalanceFile::Limit(limit)) => Rebalance::Above(c.positive(path.k("rebalance"), *limit)?),
        Some(RebalanceFile::Word(word)) if word == "never" => Rebalance::Never,
        Some(RebalanceFile::Word(word)) => {
            c.err(
                path.k("rebalance"),
                format!("must be an imbalance limit > 0 (e.g. 0.1) or \"never\", got \"{word}\""),
            );
            return None;
        }
    };
    Some(RankSettings { method, rebalance })
}
