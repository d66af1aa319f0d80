//! The README's commands run as written.
//!
//! Every ```sh block of README.md is a list of commands, one per line. The blocks that need
//! nothing but a CPU run here, in order, in a scratch folder that sees the repository's `scenes/`
//! (so `out/...` lands in the scratch folder): `sph ...` runs the binary under test. `cargo`
//! lines are the build and test commands themselves: `.ci/run` runs them on a bare copy of the
//! repository. A block that starts with `# needs the reference data` runs in the validation
//! suite (`tests/validation_data.rs`); one that starts with `# needs a GPU` is checked here to
//! parse (`sph` refuses `--backend cuda` without a GPU, which `.ci/run` checks); so is one that
//! starts with `# needs MPI` (`.ci/run` runs `sph run` under `mpirun`).

mod readme_commands;

use readme_commands::{Block, Needs, readme_blocks, run_block, words};

fn blocks() -> Vec<Block> {
    let blocks = readme_blocks();
    assert!(
        blocks.iter().any(|b| b.needs == Needs::Cpu),
        "README.md has no ```sh block to run"
    );
    blocks
}

#[test]
fn readme_starts_with_the_two_commands() {
    let first = &blocks()[0];
    assert_eq!(
        first.commands,
        [
            "cargo run --release -- run scenes/dam_break_2d.toml --out out/dam",
            "cargo test --release"
        ],
        "the README's first block is the two commands"
    );
}

#[test]
fn readme_cpu_commands_run_as_written() {
    let dir = readme_commands::scratch("cpu");
    let mut ran = 0;
    for block in blocks().iter().filter(|b| b.needs == Needs::Cpu) {
        ran += run_block(block, &dir, None);
    }
    assert!(ran >= 5, "only {ran} sph commands in the README's CPU blocks");
    // What the tour says it writes.
    assert!(dir.join("out/tour/summary.json").is_file());
    std::fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn readme_gpu_commands_parse() {
    use clap::Parser;
    let mut parsed = 0;
    for block in blocks().iter().filter(|b| b.needs == Needs::Gpu) {
        for line in &block.commands {
            let w = words(line);
            if w[0] != "sph" {
                continue;
            }
            sph::cli::Cli::try_parse_from(&w).unwrap_or_else(|e| panic!("{line}: {e}"));
            parsed += 1;
        }
    }
    assert!(parsed >= 1, "the README shows no GPU command");
}

/// The MPI blocks' `sph` commands (after `mpirun ...` where there is one) parse.
#[test]
fn readme_mpi_commands_parse() {
    use clap::Parser;
    let mut parsed = 0;
    for block in blocks().iter().filter(|b| b.needs == Needs::Mpi) {
        for line in &block.commands {
            let w = words(line);
            let Some(at) = w.iter().position(|x| x == "sph") else {
                continue;
            };
            sph::cli::Cli::try_parse_from(&w[at..]).unwrap_or_else(|e| panic!("{line}: {e}"));
            parsed += 1;
        }
    }
    assert!(parsed >= 3, "the README shows {parsed} MPI commands");
}
