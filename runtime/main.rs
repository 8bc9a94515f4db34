fn main() -> std::process::ExitCode {
    magbubble::cli::main_entry()
}
