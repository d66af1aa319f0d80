//! The `sph` command line: the only place that prints or exits.
//!
//! `sph run SCENE` runs a scene and writes its results; `sph check SCENE` validates a scene and
//! prints its particle counts, memory estimate and stage plan; `sph plan SCENE` prints what a
//! run simulates, stage by stage, with equations and fields; `sph sweep SCENE --set
//! KEY=V1,V2,...` runs one variant per value and compares them; `sph bench` times the solver at
//! several sizes on each backend; `sph surface RUN_DIR` reconstructs the free surface of a
//! finished run's frames; `sph render RUN_DIR` draws a run's frames and `sph plot RUN_DIR`
//! charts its logs; `sph waves RUN_DIR` reads the regular waves its level gauges recorded.

mod bench;
mod check;
mod compare;
mod plan;
mod plot;
mod ranks;
mod render;
mod run;
pub mod signals;
mod surface;
mod sweep;
pub mod waves;

pub use check::report as check_report;
use clap::{Parser, Subcommand, ValueEnum};
use std::path::PathBuf;

/// Incompressible free-surface SPH (Gugushvili & Evstigneev) — CPU reference solver.
#[derive(Parser, Debug)]
#[command(name = "sph", version, about)]
pub struct Cli {
    /// Directory holding the experimental reference data that scenes' probes name (their
    /// `[probe.reference] file` is relative to it); default: the environment variable
    /// SPH_REFERENCE_DIR. Without it, comparisons are skipped (docs/validation.md lists the
    /// files and their public sources).
    #[arg(long, global = true, value_name = "DIR")]
    reference_dir: Option<PathBuf>,
    #[command(subcommand)]
    command: Command,
}

/// Loads the scene at `path` with `sets`, looks its probes' reference files up in the reference
/// directory (`--reference-dir`, else `SPH_REFERENCE_DIR`) and prints one line per file that is
/// not available when `warn` (the comparison is skipped, the rest goes on).
pub fn load_located(
    path: &std::path::Path,
    sets: &[String],
    reference_dir: Option<&std::path::Path>,
    warn: bool,
) -> Result<crate::scene::Scene, crate::scene::SceneError> {
    let mut scene = crate::scene::load_scene(path, sets)?;
    let dir = crate::scene::reference_dir(reference_dir);
    for skipped in crate::scene::locate_references(&mut scene, dir.as_deref()) {
        if warn {
            eprintln!("warning: {skipped}");
        }
    }
    Ok(scene)
}

/// The error and its causes on one line, `outer: inner: ...`, leaving out a cause whose text the
/// line already holds (the library's errors name their source in their own message, so `{:#}`
/// would print an I/O error two or three times). `sph` prints it after `error: `.
pub fn one_line(e: &anyhow::Error) -> String {
    let mut line = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if line.contains(&text) {
            continue;
        }
        if !line.is_empty() {
            line.push_str(": ");
        }
        line.push_str(&text);
    }
    line
}

/// Makes a closed output pipe end the program quietly, as it ends `cat` or `grep`: restores
/// the default action of SIGPIPE (terminate), which the Rust runtime sets to "ignore" at start.
///
/// Why: with SIGPIPE ignored, a write to a pipe whose reader has gone (`sph check SCENE | head
/// -1`) fails with `EPIPE`, and `println!` turns that into a panic ("failed printing to stdout:
/// Broken pipe"). With the default action the kernel ends the process at that write, silently,
/// and the shell sees the usual status 128 + 13. Call it first thing in `main`; a no-op off unix.
pub fn quiet_broken_pipe() {
    #[cfg(unix)]
    // SAFETY: `signal` with `SIG_DFL` installs no handler (no code runs in signal context); it
    // is called at the start of `main`, before any thread is spawned.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// Backend choice on the command line.
#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum BackendArg {
    /// rayon CPU reference backend.
    Cpu,
    /// CUDA backend (needs `--features cuda` and an NVIDIA GPU).
    Cuda,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run a scene to its end time and write summary.json, frames (.vtu/.pvd) and forces.csv.
    Run {
        /// Scene file (TOML); absent with --resume.
        #[arg(required_unless_present = "resume")]
        scene: Option<PathBuf>,
        /// Output directory [default: out/<scene name>].
        #[arg(long)]
        out: Option<PathBuf>,
        /// Worker threads [default: all cores].
        #[arg(long)]
        threads: Option<usize>,
        /// Backend.
        #[arg(long, value_enum, default_value_t = BackendArg::Cpu)]
        backend: BackendArg,
        /// Override the scene's end time [s] (same as --set solver.end_time=T).
        #[arg(long)]
        end_time: Option<f64>,
        /// Override any scene key by its dotted TOML path, e.g. --set solver.dt=1e-4.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        sets: Vec<String>,
        /// Write the full state to OUT/checkpoint.bin every N steps and at the end (atomically).
        #[arg(long, value_name = "N")]
        checkpoint_every: Option<u64>,
        /// Continue the run in RUN_DIR from its checkpoint.bin (scene and settings from the
        /// checkpoint; --end-time and --set still apply).
        #[arg(long, value_name = "RUN_DIR", conflicts_with = "out")]
        resume: Option<PathBuf>,
        /// Replace another run's files in the output folder (only the files its
        /// run_manifest.json lists are removed; nothing else is touched or overwritten).
        #[arg(long, conflicts_with = "resume")]
        force: bool,
        /// With --resume: continue although the scene file changed since the run started.
        #[arg(long, requires = "resume")]
        accept_edited_scene: bool,
        /// Under mpirun (built with --features mpi): how the domain is cut among the ranks
        /// (overrides the scene's `[ranks] decomposition`; default bisection).
        #[arg(long, value_enum)]
        decomposition: Option<ranks::DecompositionArg>,
        /// Under mpirun: cut the domain again when the ranks' particle counts differ by more
        /// than this imbalance (max/mean - 1), or `never` (overrides the scene's
        /// `[ranks] rebalance`; default 0.1).
        #[arg(long, value_name = "LIMIT", value_parser = ranks::parse_rebalance)]
        rebalance: Option<crate::distributed::Rebalance>,
    },
    /// Run one variant of a scene per value of the swept keys and compare them: writes sweep.csv,
    /// sweep.png (error against wall time), fronts.png (probe curves with reference data) and
    /// pareto.png (error against wall time per simulated second, one line per solver).
    Sweep {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Output directory [default: out/<scene file stem>-sweep]; variant k runs in DIR/<k>-<variant>.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Worker threads [default: all cores].
        #[arg(long)]
        threads: Option<usize>,
        /// Backend.
        #[arg(long, value_enum, default_value_t = BackendArg::Cpu)]
        backend: BackendArg,
        /// Override the scene's end time [s] in every variant (same as --set solver.end_time=T).
        #[arg(long)]
        end_time: Option<f64>,
        /// A scene key and its values, split on commas outside brackets and quotes, e.g.
        /// --set solver.delta=1e-2,1e-3 or --set 'effects=["gravity"],["gravity","viscosity"]'.
        /// Several swept keys give every combination (first key varying slowest); a single value
        /// applies to all variants.
        #[arg(long = "set", value_name = "KEY=V1,V2,...")]
        sets: Vec<String>,
        /// Compare the solvers instead of sweeping keys: `wcsph=C1,C2,...` runs wcsph at each
        /// sound speed [m/s], `corrected=D1,D2,...` runs corrected at each tolerance delta;
        /// repeat for both. Adds pareto.png (error against wall time per simulated second, one
        /// line per solver); every --set then takes one value.
        #[arg(long = "solvers", value_name = "KIND=V1,V2,...")]
        solvers: Vec<String>,
        /// Replace another sweep's files in the output folder (only files sph listed as its own).
        #[arg(long)]
        force: bool,
    },
    /// Time the solver at several particle counts on each backend (the paper's Fig. 5): prints
    /// the table and writes bench.csv (and with --plot bench.png).
    Bench {
        /// Scene to rescale to each size.
        #[arg(long, default_value = "scenes/dam_break_column_3d.toml")]
        scene: PathBuf,
        /// Backends, comma-separated.
        #[arg(long, value_enum, value_delimiter = ',', default_value = "cpu")]
        backend: Vec<BackendArg>,
        /// Particle counts to aim for, comma-separated (e.g. 1e4,1e5,1e6).
        #[arg(long, value_delimiter = ',', default_value = "1e4,1e5")]
        sizes: Vec<String>,
        /// Timed steps per row.
        #[arg(long, default_value_t = 5)]
        steps: usize,
        /// Timed sweeps per row.
        #[arg(long, default_value_t = 10)]
        sweeps: usize,
        /// Output directory for bench.csv [default: out/bench].
        #[arg(long)]
        out: Option<PathBuf>,
        /// CPU worker threads [default: all cores].
        #[arg(long)]
        threads: Option<usize>,
        /// Override any scene key by its dotted TOML path.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        sets: Vec<String>,
        /// Also write bench.png: time per step against particles, log-log, one line per backend.
        #[arg(long)]
        plot: bool,
        /// Instead, the scaling table of runs split across these rank counts (e.g. 1,2,4):
        /// ranks as threads of this process sharing --threads; writes bench_scaling.csv.
        #[arg(long, value_delimiter = ',')]
        ranks: Vec<usize>,
    },
    /// Draw one probe of several finished runs (their probes.csv) against the scene's
    /// reference data on one figure, and print each run's error or force peak.
    Compare {
        /// Scene the runs came from (for the probe and its reference data).
        scene: PathBuf,
        /// A run to draw, as LABEL=DIR (DIR holds its probes.csv; split at the last `=`); repeat.
        #[arg(long = "run", value_name = "LABEL=DIR", required = true)]
        runs: Vec<String>,
        /// Probe name.
        #[arg(long)]
        probe: String,
        /// Figure to write (PNG).
        #[arg(long, default_value = "compare.png")]
        out: PathBuf,
        /// Draw only t <= T [s] (the probe's own time axis).
        #[arg(long)]
        t_max: Option<f64>,
        /// Override any scene key by its dotted TOML path.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        sets: Vec<String>,
    },
    /// Draw a run's frames as PNG pictures (the paper's Figs. 2-3): particles coloured by a
    /// field on one fixed scale for the whole run, solids grey, the time in a corner.
    Render {
        /// The run's output directory (holds particles.pvd and frames/).
        run_dir: PathBuf,
        /// Draw every N-th frame (frame 0 first).
        #[arg(long, value_name = "N", default_value_t = 1)]
        every: usize,
        /// View of a 3D run (2D runs: side, their x-y plane).
        #[arg(long, value_enum, default_value_t = render::ViewArg::Side)]
        view: render::ViewArg,
        /// Field colouring the fluid.
        #[arg(long, value_enum, default_value_t = render::ColorArg::Speed)]
        color: render::ColorArg,
        /// Image width [px]; the height follows the picture.
        #[arg(long, default_value_t = 1200)]
        width: u32,
        /// Output directory [default: RUN_DIR/render_<view>_<color>].
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Chart a run's CSV logs as PNGs: force on each solid (Fig. 4), probes, compression and
    /// free-surface deficit, correction iterations and time step per step.
    Plot {
        /// The run's output directory.
        run_dir: PathBuf,
        /// The run's scene: its probes with reference data are also drawn against it.
        #[arg(long)]
        scene: Option<PathBuf>,
        /// Override a key of --scene by its dotted TOML path (as given to the run).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        sets: Vec<String>,
        /// Output directory [default: RUN_DIR/plots].
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Read the regular waves a run's level gauges recorded: each gauge's height, and the incident
    /// and reflected waves fitted to all of them (Mansard & Funke, with decay), with the
    /// reflection coefficient and the wavenumber against the dispersion relation.
    Waves {
        /// The run's output directory (holds probes.csv).
        run_dir: PathBuf,
        /// The run's scene [default: the one summary.json names].
        #[arg(long)]
        scene: Option<PathBuf>,
        /// Override a key of --scene by its dotted TOML path (as given to the run).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        sets: Vec<String>,
        /// Wave period [s] [default: the scene's wave maker's].
        #[arg(long)]
        period: Option<f64>,
        /// Still-water depth [m] [default: the scene's wave maker's].
        #[arg(long)]
        depth: Option<f64>,
        /// The level probes to use, by name, comma-separated [default: every level probe].
        #[arg(long, value_delimiter = ',')]
        gauges: Vec<String>,
        /// Window start [s] [default: four periods before its end].
        #[arg(long)]
        from: Option<f64>,
        /// Window end [s] [default: the record's end].
        #[arg(long)]
        to: Option<f64>,
        /// Where along the flume [m] to give the reflection coefficient [default: the last gauge].
        #[arg(long)]
        at: Option<f64>,
        /// The flume's axis.
        #[arg(long, default_value = "x", value_parser = ["x", "y", "z"])]
        axis: String,
    },
    /// Reconstruct the free surface (eq. 25) of every frame of a finished run: writes
    /// RUN_DIR/surface/surface_NNNNN.vtp and the series RUN_DIR/surface.pvd.
    Surface {
        /// Output directory of a finished `sph run` (holds summary.json and particles.pvd).
        run_dir: PathBuf,
        /// Support radius R of eq. (25) in particle spacings (smaller: sharper edges and
        /// corners, bumpier curved surfaces; see docs/free-surface.md).
        #[arg(long, value_name = "R", default_value_t = crate::surface::DEFAULT_RADIUS)]
        radius: f64,
    },
    /// Print what a run of the scene simulates: the stages of each integrator stage in order,
    /// each with its equation (PAPER.md numbering) and the particle fields it reads and writes,
    /// the correction loop and guards inside them, and the probes and output after each step.
    Plan {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Override any scene key by its dotted TOML path.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        sets: Vec<String>,
    },
    /// Validate a scene; print particle counts, memory needed and the stage plan.
    Check {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Override any scene key by its dotted TOML path.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        sets: Vec<String>,
    },
}

/// Parses `args` and runs the command.
pub fn run<I, T>(args: I) -> anyhow::Result<()>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let cli = Cli::try_parse_from(args).unwrap_or_else(|e| e.exit());
    let refs = cli.reference_dir.as_deref();
    match cli.command {
        Command::Run {
            scene,
            out,
            threads,
            backend,
            end_time,
            mut sets,
            checkpoint_every,
            resume,
            force,
            accept_edited_scene,
            decomposition,
            rebalance,
        } => {
            if let Some(t) = end_time {
                sets.push(format!("solver.end_time={t:e}"));
            }
            let checkpoint = run::CheckpointArgs {
                every: checkpoint_every,
                resume,
                force,
                accept_edited_scene,
            };
            sets.extend(ranks::scene_overrides(decomposition, rebalance));
            let ranks = ranks::join()?;
            run::run(
                scene.as_deref(),
                out,
                threads,
                backend,
                &sets,
                checkpoint,
                refs,
                ranks,
            )
        }
        Command::Sweep {
            scene,
            out,
            threads,
            backend,
            end_time,
            mut sets,
            solvers,
            force,
        } => {
            if let Some(t) = end_time {
                sets.push(format!("solver.end_time={t:e}"));
            }
            let out = sweep::SweepOut { dir: out, force };
            sweep::sweep(&scene, out, threads, backend, &sets, &solvers, refs)
        }
        Command::Check { scene, sets } => check::check(&scene, &sets, refs),
        Command::Plan { scene, sets } => plan::print_plan(&scene, &sets),
        Command::Surface { run_dir, radius } => surface::surface(&run_dir, radius),
        Command::Compare {
            scene,
            runs,
            probe,
            out,
            t_max,
            sets,
        } => compare::compare(&scene, &runs, &probe, &out, t_max, &sets, refs),
        Command::Bench {
            scene,
            backend,
            sizes,
            steps,
            sweeps,
            out,
            threads,
            sets,
            plot,
            ranks,
        } => {
            if ranks.is_empty() {
                bench::run_bench(&scene, out, threads, &backend, &sizes, steps, sweeps, &sets, plot)
            } else {
                bench::run_scaling(&scene, out, threads, &ranks, &sizes, steps, &sets)
            }
        }
        Command::Render {
            run_dir,
            every,
            view,
            color,
            width,
            out,
        } => render::render(&run_dir, out, every, view, color, width),
        Command::Plot {
            run_dir,
            scene,
            sets,
            out,
        } => plot::plot(&run_dir, out, scene.as_deref(), &sets, refs),
        Command::Waves {
            run_dir,
            scene,
            sets,
            period,
            depth,
            gauges,
            from,
            to,
            at,
            axis,
        } => {
            let scene = plot::scene_of_run(&run_dir, scene.as_deref(), &sets, refs)?;
            let options = waves::WaveOptions {
                period,
                depth,
                gauges,
                from,
                to,
                at,
                axis: ["x", "y", "z"].iter().position(|a| *a == axis).unwrap_or(0),
            };
            waves::waves(&run_dir, scene.as_ref(), &options)
        }
    }
}
