//! `nanobeam` CLI: parse, dispatch to `nanobeam::cli`, map errors to exit codes.

fn main() {
    tune_allocator();
    let cli: nanobeam::cli::Cli = nanobeam::cli::clap_error::parse_or_exit();
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    if let Err(e) = nanobeam::cli::run(cli, &mut out) {
        eprintln!("{e}");
        std::process::exit(e.exit_code());
    }
}

/// glibc's malloc serves blocks ≥ 128 KiB with a fresh `mmap` and returns
/// freed heap tops to the kernel, so the per-parameter R̂/ESS vectors of a
/// calibration (80 000 f64 = 640 KiB each) and the output buffers page-fault
/// anew on every use, a measurable part of a `calibrate` (`benches/README.md`, "Measurements cited by src/").
/// Serving blocks below 32 MiB (glibc's largest allowed threshold on 64-bit)
/// from the heap and keeping up to 256 MiB of freed memory halves the faults
/// (3 436). Speed only: no result depends on where memory comes from. Only
/// glibc has `mallopt`; elsewhere the allocator's defaults stay.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn tune_allocator() {
    // SAFETY: mallopt only sets allocator parameters (a failure leaves the
    // default, which is harmless); it runs before any other thread exists.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 32 << 20);
        libc::mallopt(libc::M_TRIM_THRESHOLD, 256 << 20);
    }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn tune_allocator() {}
