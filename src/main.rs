//! `nanobeam` CLI: parse, dispatch to `nanobeam::cli`, map errors to exit codes.

use clap::Parser;

fn main() {
    let cli = nanobeam::cli::Cli::parse();
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    if let Err(e) = nanobeam::cli::run(cli, &mut out) {
        eprintln!("{e}");
        std::process::exit(e.exit_code());
    }
}
