// The unwinder linked statically (libgcc_eh, what gcc's `-static-libgcc` links) instead of std's
// default libgcc_s.so.1: the process no longer maps libgcc_s nor runs its constructor (a `cpuid`
// probe, a VM exit on this machine). Panics still unwind and `catch_unwind` still catches them:
// a cancelled run unwinds out of the integrator to api/run.rs (tests/suite/cli_signal.rs).
// Linked before std and whole, so `--as-needed` drops libgcc_s (issue 34, docs/performance.md
// "Radial runs against APECSS").
#[cfg(all(target_os = "linux", target_env = "gnu"))]
#[link(name = "gcc_eh", kind = "static", modifiers = "-bundle,+whole-archive")]
extern "C" {}

fn main() -> std::process::ExitCode {
    magbubble::cli::main_entry()
}
