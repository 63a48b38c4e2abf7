//! `omniad-tui`: the terminal UI on its own.
fn main() -> std::process::ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match omniad_tui::run_with_args(&args) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("omniad-tui: error: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
