//! The peer: MuJoCo's ellipsoid fluid model on 1,000 free 30 x 50 x 2 cm
//! plates (contacts off, RK4 at 1/240 s, one thread), measured in the same
//! run by `scripts/mujoco_peer.py` when `python3 -c "import mujoco"` works.

use std::path::PathBuf;
use std::process::Command;

/// MuJoCo's figures.
#[derive(Clone, Debug)]
pub struct Peer {
    /// Body-steps per second, one thread, RK4.
    pub body_steps_per_second: f64,
    /// The same with MuJoCo's default Euler integrator (for reference).
    pub euler_body_steps_per_second: f64,
    /// Bodies simulated.
    pub bodies: u64,
    /// MuJoCo's version.
    pub version: String,
}

/// The script: beside the sources, else `scripts/` under the working
/// directory.
fn script() -> Option<PathBuf> {
    let built = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scripts/mujoco_peer.py"
    ));
    [built, PathBuf::from("scripts/mujoco_peer.py")]
        .into_iter()
        .find(|p| p.is_file())
}

/// Runs the script, or says why not.
pub fn measure(quick: bool) -> Result<Peer, String> {
    let import = Command::new("python3")
        .args(["-c", "import mujoco"])
        .output()
        .map_err(|e| format!("python3 not runnable: {e}"))?;
    if !import.status.success() {
        return Err("python3 cannot import mujoco (pip install mujoco)".into());
    }
    let path = script().ok_or("scripts/mujoco_peer.py not found")?;
    let mut cmd = Command::new("python3");
    cmd.arg(&path);
    if quick {
        cmd.arg("--quick");
    }
    let out = cmd
        .output()
        .map_err(|e| format!("running {}: {e}", path.display()))?;
    if !out.status.success() {
        return Err(format!(
            "{} failed: {}",
            path.display(),
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    let v: serde_json::Value = serde_json::from_slice(&out.stdout)
        .map_err(|e| format!("{} printed no JSON: {e}", path.display()))?;
    let rate = v["body_steps_per_second"]
        .as_f64()
        .ok_or("the script's JSON has no body_steps_per_second")?;
    Ok(Peer {
        body_steps_per_second: rate,
        euler_body_steps_per_second: v["euler_body_steps_per_second"].as_f64().unwrap_or(0.0),
        bodies: v["bodies"].as_u64().unwrap_or(0),
        version: v["version"].as_str().unwrap_or("?").to_string(),
    })
}
