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
        eprintln!("error: {}", one_line(&e));
        std::process::exit(sph::cli::signals::exit_status(&e));
    }
}

/// The error and its causes on one line, `outer: inner: ...`, leaving out a cause whose text the
/// line already holds (the library's errors name their source in their own message, so `{:#}`
/// would print an I/O error two or three times).
fn one_line(e: &anyhow::Error) -> String {
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
