//! `nanobeam` CLI: parse, dispatch to `nanobeam::cli`, map errors to exit codes.

fn main() {
    let cli: nanobeam::cli::Cli = nanobeam::cli::clap_error::parse_or_exit();
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    if let Err(e) = nanobeam::cli::run(cli, &mut out) {
        eprintln!("{e}");
        std::process::exit(e.exit_code());
    }
}
