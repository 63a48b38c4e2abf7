//! End-to-end: the real `omniad-tui` binary driven in tmux (send-keys,
//! capture-pane). Skipped, with a notice, when tmux is not installed.

use std::process::Command;
use std::thread::sleep;
use std::time::{Duration, Instant};

fn tmux(args: &[&str]) -> Option<String> {
    let out = Command::new("tmux").args(args).output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).into_owned())
}

/// A tmux session that is killed (by name) when dropped.
struct Session(String);

impl Session {
    fn capture(&self) -> String {
        tmux(&["capture-pane", "-p", "-t", &self.0]).unwrap_or_default()
    }
    fn keys(&self, keys: &[&str]) {
        for k in keys {
            tmux(&["send-keys", "-t", &self.0, k]);
            sleep(Duration::from_millis(150));
        }
    }
    /// Waits up to 20 s for `text` on the screen.
    fn wait_for(&self, text: &str) -> String {
        let start = Instant::now();
        loop {
            let screen = self.capture();
            if screen.contains(text) || start.elapsed() > Duration::from_secs(20) {
                return screen;
            }
            sleep(Duration::from_millis(100));
        }
    }
}

impl Drop for Session {
    fn drop(&mut self) {
        tmux(&["kill-session", "-t", &self.0]);
    }
}

#[test]
fn the_binary_runs_switches_views_and_restores_the_terminal() {
    if tmux(&["-V"]).is_none() {
        println!("NOTICE: tmux not found; skipping the end-to-end TUI test");
        return;
    }
    let bin = env!("CARGO_BIN_EXE_omniad-tui");
    let name = format!("omniad-tui-e2e-{}", std::process::id());
    let cmd = format!("NO_COLOR=1 {bin} --no-mouse; echo EXITED-$?; sleep 30");
    tmux(&[
        "new-session",
        "-d",
        "-s",
        &name,
        "-x",
        "80",
        "-y",
        "24",
        &cmd,
    ])
    .expect("tmux session");
    let s = Session(name);

    let screen = s.wait_for("Telemetry");
    assert!(
        screen.contains("[1 Sphere]") && screen.contains("probe"),
        "{screen}"
    );
    s.keys(&["2"]);
    assert!(s.wait_for("equilibrium").contains("stability"), "kite view");
    s.keys(&["3", " "]);
    assert!(
        s.wait_for("running").contains("bodies 400"),
        "simulation runs"
    );
    s.keys(&[" ", "4"]);
    assert!(
        s.wait_for("tether force").contains("Kitepower"),
        "telemetry"
    );
    s.keys(&["?"]);
    assert!(s.wait_for("keys: Telemetry").contains("seek"), "help");
    s.keys(&["Escape"]);
    sleep(Duration::from_millis(300));
    tmux(&["resize-window", "-t", &s.0, "-x", "30", "-y", "10"]);
    let small = s.wait_for("too small");
    assert!(small.contains("too small"), "{small}");
    tmux(&["resize-window", "-t", &s.0, "-x", "80", "-y", "24"]);
    assert!(s.wait_for("tether force").contains("tether force"));
    s.keys(&["C-c"]);
    let done = s.wait_for("EXITED-");
    assert!(done.contains("EXITED-0"), "Ctrl-C exits cleanly: {done}");
    assert!(!done.contains("Telemetry"), "alternate screen left: {done}");
}

#[test]
fn a_panic_restores_the_terminal() {
    if tmux(&["-V"]).is_none() {
        println!("NOTICE: tmux not found; skipping the panic-hook TUI test");
        return;
    }
    let bin = env!("CARGO_BIN_EXE_omniad-tui");
    let name = format!("omniad-tui-panic-{}", std::process::id());
    let cmd = format!(
        "OMNIAD_TUI_TEST_PANIC=1 RUST_BACKTRACE=0 {bin} --no-mouse; echo EXITED-$?; stty -a | tr ' ' '\\n' | grep -x -- '-*icanon'; sleep 30"
    );
    tmux(&[
        "new-session",
        "-d",
        "-s",
        &name,
        "-x",
        "100",
        "-y",
        "30",
        &cmd,
    ])
    .expect("tmux session");
    let s = Session(name);
    let done = s.wait_for("icanon");
    assert!(done.contains("EXITED-101"), "panicked: {done}");
    assert!(
        done.contains("testing that the terminal is restored"),
        "message printed: {done}"
    );
    assert!(!done.contains("Telemetry"), "alternate screen left: {done}");
    assert!(
        done.lines().any(|l| l.trim() == "icanon"),
        "raw mode off (icanon): {done}"
    );
}

/// `kill -SIG` from outside (a closed SSH session sends HUP) must leave the
/// terminal as `q` does: raw mode off, main screen, mouse reporting off.
#[test]
fn signals_restore_the_terminal() {
    if tmux(&["-V"]).is_none() {
        println!("NOTICE: tmux not found; skipping the signal TUI test");
        return;
    }
    let bin = env!("CARGO_BIN_EXE_omniad-tui");
    for (sig, code) in [("TERM", 143), ("INT", 130), ("HUP", 129)] {
        let name = format!("omniad-tui-sig{sig}-{}", std::process::id());
        let go = std::env::temp_dir().join(format!("{name}.go"));
        let _ = std::fs::remove_file(&go);
        // The TUI runs in the background of the pane's shell so that the
        // shell can kill it (once the test has seen it drawn) and then
        // report the terminal's state.
        let cmd = format!(
            "NO_COLOR=1 {bin} & pid=$!; while [ ! -e {go} ]; do sleep 0.1; done; \
             kill -{sig} $pid; wait $pid; echo EXITED-$?; \
             stty -a | tr ' ' '\\n' | grep -x -- '-*icanon'; sleep 30",
            go = go.display()
        );
        tmux(&[
            "new-session",
            "-d",
            "-s",
            &name,
            "-x",
            "100",
            "-y",
            "30",
            &cmd,
        ])
        .expect("tmux session");
        let s = Session(name);
        let up = s.wait_for("Telemetry");
        assert!(up.contains("Telemetry"), "{sig}: the TUI is drawn: {up}");
        std::fs::write(&go, b"").expect("go file");
        let done = s.wait_for("icanon");
        let _ = std::fs::remove_file(&go);
        assert!(done.contains(&format!("EXITED-{code}")), "{sig}: {done}");
        assert!(
            !done.contains("Telemetry"),
            "{sig}: alternate screen left: {done}"
        );
        assert!(
            done.lines().any(|l| l.trim() == "icanon"),
            "{sig}: raw mode off (icanon): {done}"
        );
        let flags = tmux(&[
            "display-message",
            "-p",
            "-t",
            &s.0,
            "#{alternate_on}#{mouse_any_flag}",
        ])
        .unwrap_or_default();
        assert_eq!(flags.trim(), "00", "{sig}: alternate screen and mouse off");
    }
}
