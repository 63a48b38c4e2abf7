//! `omniad` with no command opens the terminal UI (issue 5): driven in
//! tmux (send-keys, capture-pane); skipped with a notice without tmux.

use std::process::Command;
use std::thread::sleep;
use std::time::{Duration, Instant};

fn tmux(args: &[&str]) -> Option<String> {
    let out = Command::new("tmux").args(args).output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).into_owned())
}

fn wait_for(session: &str, text: &str) -> String {
    let start = Instant::now();
    loop {
        let screen = tmux(&["capture-pane", "-p", "-t", session]).unwrap_or_default();
        if screen.contains(text) || start.elapsed() > Duration::from_secs(20) {
            return screen;
        }
        sleep(Duration::from_millis(100));
    }
}

#[test]
fn omniad_without_a_command_opens_the_tui() {
    if tmux(&["-V"]).is_none() {
        println!("NOTICE: tmux not found; skipping the omniad TUI test");
        return;
    }
    let bin = env!("CARGO_BIN_EXE_omniad");
    let session = format!("omniad-cli-tui-{}", std::process::id());
    let cmd = format!("{bin}; echo EXITED-$?; sleep 30");
    tmux(&[
        "new-session",
        "-d",
        "-s",
        &session,
        "-x",
        "80",
        "-y",
        "24",
        &cmd,
    ])
    .expect("tmux session");
    let screen = wait_for(&session, "Telemetry");
    let ok = screen.contains("[1 Sphere]") && screen.contains("plate.omni");
    tmux(&["send-keys", "-t", &session, "q"]);
    let done = wait_for(&session, "EXITED-");
    tmux(&["kill-session", "-t", &session]);
    assert!(ok, "TUI on the bundled plate: {screen}");
    assert!(done.contains("EXITED-0"), "{done}");
}
