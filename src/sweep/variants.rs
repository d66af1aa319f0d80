//! What a sweep runs: the variants of its `--set` overrides ([`Sweep`]), their scenes and
//! their folders ([`variant_dir`]).

use super::SweepError;
use crate::scene::{Scene, load_scene};
use std::path::{Path, PathBuf};

/// Longest sanitised variant name in a directory name [characters].
const MAX_DIR_NAME: usize = 80;

/// Splits an override's value list on the commas outside brackets, braces and quotes; each
/// value is trimmed. `"1e-2,1e-3"` gives two values, `"[0,-9.81]"` one and
/// `r#"["gravity"],["gravity","viscosity"]"#` two.
pub fn split_values(text: &str) -> Vec<String> {
    let mut values = Vec::new();
    let mut depth = 0usize;
    let mut quote: Option<char> = None;
    let mut escaped = false;
    let mut current = String::new();
    for c in text.chars() {
        match quote {
            Some(q) => {
                if escaped {
                    escaped = false;
                } else if c == '\\' && q == '"' {
                    escaped = true;
                } else if c == q {
                    quote = None;
                }
            }
            None => match c {
                '"' | '\'' => quote = Some(c),
                '[' | '{' => depth += 1,
                ']' | '}' => depth = depth.saturating_sub(1),
                ',' if depth == 0 => {
                    values.push(current.trim().to_string());
                    current.clear();
                    continue;
                }
                _ => {}
            },
        }
        current.push(c);
    }
    values.push(current.trim().to_string());
    values
}

/// One run of a sweep.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Variant {
    /// The swept values, `KEY=VALUE` joined by spaces (`solver.delta=1e-3 solver.kind=corrected`);
    /// `base` when nothing is swept.
    pub name: String,
    /// The value of each swept key ([`Sweep::keys`]), as written.
    pub values: Vec<String>,
    /// Every override of this variant (`KEY=VALUE`, in command-line order), for [`load_scene`].
    pub sets: Vec<String>,
}

/// The variants of a sweep.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Sweep {
    /// The swept keys (given with several values), in command-line order.
    pub keys: Vec<String>,
    /// The Cartesian product of the swept values, first key varying slowest.
    pub variants: Vec<Variant>,
}

impl Sweep {
    /// The variants of `sets` (each `KEY=V1,V2,...`, see [`split_values`]).
    ///
    /// # Errors
    /// A set without `=`, an empty key or value, or a swept key given twice.
    pub fn from_sets(sets: &[String]) -> Result<Self, SweepError> {
        let mut parsed: Vec<(String, Vec<String>)> = Vec::new();
        for set in sets {
            let Some((key, list)) = set.split_once('=') else {
                return Err(SweepError::MissingEquals { set: set.clone() });
            };
            let key = key.trim();
            if key.is_empty() {
                return Err(SweepError::EmptyValue {
                    set: set.clone(),
                    reason: "empty KEY before '='".into(),
                });
            }
            let values = split_values(list);
            if values.iter().any(String::is_empty) {
                return Err(SweepError::EmptyValue {
                    set: set.clone(),
                    reason: "empty value (expected KEY=V1,V2,...)".into(),
                });
            }
            parsed.push((key.to_string(), values));
        }
        let keys: Vec<String> = parsed
            .iter()
            .filter(|(_, v)| v.len() > 1)
            .map(|(k, _)| k.clone())
            .collect();
        for key in &keys {
            if parsed.iter().filter(|(k, _)| k == key).count() > 1 {
                return Err(SweepError::DuplicateKey { key: key.clone() });
            }
        }
        // Odometer over the swept sets, the last one varying fastest.
        let swept: Vec<usize> = (0..parsed.len()).filter(|&i| parsed[i].1.len() > 1).collect();
        let count: usize = swept.iter().map(|&i| parsed[i].1.len()).product();
        let mut variants = Vec::with_capacity(count);
        let mut choice = vec![0usize; parsed.len()];
        for _ in 0..count {
            let sets = parsed
                .iter()
                .zip(&choice)
                .map(|((k, v), &c)| format!("{k}={}", v[c]))
                .collect();
            let values: Vec<String> = swept.iter().map(|&i| parsed[i].1[choice[i]].clone()).collect();
            let name = if keys.is_empty() {
                "base".to_string()
            } else {
                keys.iter()
                    .zip(&values)
                    .map(|(k, v)| format!("{k}={v}"))
                    .collect::<Vec<_>>()
                    .join(" ")
            };
            variants.push(Variant { name, values, sets });
            for &i in swept.iter().rev() {
                choice[i] += 1;
                if choice[i] < parsed[i].1.len() {
                    break;
                }
                choice[i] = 0;
            }
        }
        Ok(Self { keys, variants })
    }

    /// Loads and validates the scene of every variant, before anything runs.
    ///
    /// # Errors
    /// [`SweepError::InvalidVariant`] for the first variant that does not load, naming the
    /// overrides its problems point at.
    pub fn load(&self, path: &Path) -> Result<Vec<Scene>, SweepError> {
        let count = self.variants.len();
        self.variants
            .iter()
            .enumerate()
            .map(|(i, v)| {
                load_scene(path, &v.sets).map_err(|source| {
                    let mut settings: Vec<String> = Vec::new();
                    for p in source.problems() {
                        if let crate::scene::Location::Override(key) = &p.location {
                            for set in &v.sets {
                                let matches = set.split_once('=').is_some_and(|(k, _)| k.trim() == key);
                                if matches && !settings.contains(set) {
                                    settings.push(set.clone());
                                }
                            }
                        }
                    }
                    SweepError::InvalidVariant {
                        index: i + 1,
                        count,
                        variant: v.name.clone(),
                        settings,
                        source,
                    }
                })
            })
            .collect()
    }

    /// The header of `sweep.csv` for scenes whose probes with reference data are `probes`:
    /// `variant`, one column per swept key, `wall_s`, `wall_s_per_simulated_s`,
    /// `particle_steps_per_s`, `steps`,
    /// `correction_iterations_mean` (per corrected stage), `correction_iterations_max`,
    /// `velocity_iterations_mean` (per velocity solve), `operator_applications_per_stage` (both
    /// per corrected stage), `unconverged_stages`, `max_compression`, `max_surface_deficit` (the summary's, see
    /// [`Summary::max_compression`]), `<probe>_relative_error_max` and
    /// `<probe>_relative_error_mean` per probe, `status`.
    pub fn columns(&self, probes: &[String]) -> Vec<String> {
        let mut columns = vec!["variant".to_string()];
        columns.extend(self.keys.iter().cloned());
        columns.extend(
            [
                "wall_s",
                "wall_s_per_simulated_s",
                "particle_steps_per_s",
                "steps",
                "correction_iterations_mean",
                "correction_iterations_max",
                "velocity_iterations_mean",
                "operator_applications_per_stage",
                "unconverged_stages",
                "max_compression",
                "max_surface_deficit",
            ]
            .map(String::from),
        );
        for p in probes {
            columns.push(format!("{p}_relative_error_max"));
            columns.push(format!("{p}_relative_error_mean"));
        }
        columns.push("status".into());
        columns
    }
}

/// The directory of variant `index` (0-based) of `count` in `out`:
/// `<index+1>-<name>`, the index zero-padded to the width of `count`, the name reduced to
/// `[A-Za-z0-9._-]` (other runs of characters become one `_`).
pub fn variant_dir(out: &Path, index: usize, count: usize, variant: &Variant) -> PathBuf {
    let width = count.to_string().len();
    let mut name = String::new();
    for c in variant.name.chars() {
        if c.is_ascii_alphanumeric() || matches!(c, '.' | '-') {
            name.push(c);
        } else if !name.ends_with('_') {
            name.push('_');
        }
    }
    let name: String = name.trim_matches('_').chars().take(MAX_DIR_NAME).collect();
    out.join(format!("{:0width$}-{name}", index + 1))
}
