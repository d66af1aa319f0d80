//! The `sph` command-line tool; see `sph --help`.

/// The system allocator, leaving a run's `failed` status behind when memory runs out.
#[global_allocator]
static ALLOCATOR: sph::run::out_of_memory::FailureAware = sph::run::out_of_memory::FailureAware;

fn main() {
    sph::cli::quiet_broken_pipe();
    if let Some(bytes) = std::env::var(sph::run::out_of_memory::FAIL_ALLOCATIONS_ABOVE_VAR)
        .ok()
        .and_then(|v| v.parse().ok())
    {
        sph::run::out_of_memory::fail_allocations_above(bytes);
    }
    if let Err(e) = sph::cli::run(std::env::args_os()) {
        eprintln!("error: {}", sph::cli::one_line(&e));
        std::process::exit(sph::cli::signals::exit_status(&e));
    }
}
