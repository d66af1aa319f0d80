//! The `sph` command-line tool; see `sph --help`.

fn main() {
    if let Err(e) = sph::cli::run(std::env::args_os()) {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
