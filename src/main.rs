fn main() -> std::process::ExitCode {
    rocklab::cli::main()
}
