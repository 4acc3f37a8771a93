//! The `chaindrive` command-line tool; everything it does is in
//! `chaindrive::cli`.

fn main() -> std::process::ExitCode {
    chaindrive::cli::main()
}
