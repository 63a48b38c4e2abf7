//! `omniad bench`: the fixed speed suite of `omniad-bench` (issue 19), each
//! figure with its ratio to the paper's and, for the many-body figure, to
//! MuJoCo's measured in the same run.

use anyhow::Result;
use clap::Args;
use omniad_bench::{paper, Report};
use serde_json::{json, Value};

/// Arguments of `omniad bench`.
#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Print a JSON report on stdout.
    #[arg(long)]
    pub json: bool,
    /// Shorter measurements (noisier).
    #[arg(long)]
    pub quick: bool,
}

/// Runs `omniad bench`.
pub fn run(a: &BenchArgs) -> Result<()> {
    let r = omniad_bench::run(a.quick);
    if a.json {
        println!("{}", serde_json::to_string_pretty(&report(&r))?);
    } else {
        summary(&r);
    }
    Ok(())
}

fn report(r: &Report) -> Value {
    let p = &r.physics;
    let peer = match &r.peer {
        Ok(m) => json!({
            "body_steps_per_second_per_thread": m.body_steps_per_second,
            "euler_body_steps_per_second_per_thread": m.euler_body_steps_per_second,
            "bodies": m.bodies,
            "mujoco_version": m.version,
            "ours_over_peer": p.body_steps_per_second_per_thread / m.body_steps_per_second,
        }),
        Err(_) => Value::Null,
    };
    let tui = match &r.tui {
        Ok(t) => json!({
            "bodies": t.bench.bodies,
            "frames": t.bench.frames,
            "terminal": format!("{}x{}", t.bench.size.0, t.bench.size.1),
            "physics_ms": t.physics_ms,
            "draw_ms": t.draw_ms,
            "frame_ms": t.frame_ms,
            "worst_frame_ms": t.worst_frame_ms,
            "fps": t.fps(),
        }),
        Err(_) => Value::Null,
    };
    let models: serde_json::Map<String, Value> = r
        .models
        .iter()
        .map(|m| (m.kind.name().to_string(), json!(m.rk4_ns)))
        .collect();
    json!({
        "eval_single_ns": p.eval_single_ns,
        "eval_batch_ns": p.eval_batch_ns,
        "eval_single_f64_ns": p.eval_single_f64_ns,
        "eval_batch_f64_ns": p.eval_batch_f64_ns,
        "batch_over_single": p.eval_batch_ns / p.eval_single_ns,
        "rk4_single_ns": p.rk4_single_ns,
        "rk4_step_ns_by_model": models,
        "body_steps_per_second_per_thread": p.body_steps_per_second_per_thread,
        "body_steps_per_second_all_cores": p.body_steps_per_second_all_cores,
        "threads": p.threads,
        "bodies_realtime": p.bodies_realtime,
        "fit_seconds": r.fit_seconds.as_ref().ok(),
        "fit_error": r.fit_seconds.as_ref().err(),
        "fit_set": "13 takes (omniad synth plate, 8 drops + 5 spins, seed 1) generated to a temporary folder at bench time",
        "peer": peer,
        "peer_reason": r.peer.as_ref().err(),
        "tui": tui,
        "tui_error": r.tui.as_ref().err(),
        "paper": {"eval_ns": paper::EVAL_NS, "bodies_realtime": paper::BODIES_REALTIME, "fit_seconds": paper::FIT_SECONDS},
    })
}

fn summary(r: &Report) {
    let p = &r.physics;
    let x = |a: f64, b: f64| a / b;
    println!("figure                                   this run        paper      ratio");
    println!(
        "one evaluation, f32, N = 8            {:>9.1} ns   {:>7.0} ns   1/{:.0}",
        p.eval_single_ns,
        paper::EVAL_NS,
        x(paper::EVAL_NS, p.eval_single_ns)
    );
    println!(
        "batch, per body, f32                  {:>9.1} ns   {:>7.0} ns   1/{:.0}  ({:.2} x single)",
        p.eval_batch_ns,
        paper::EVAL_NS,
        x(paper::EVAL_NS, p.eval_batch_ns),
        x(p.eval_batch_ns, p.eval_single_ns)
    );
    println!(
        "one evaluation / batch, f64           {:>9.1} / {:.1} ns",
        p.eval_single_f64_ns, p.eval_batch_f64_ns
    );
    println!(
        "RK4 step, one body, f64               {:>9.1} ns",
        p.rk4_single_ns
    );
    let per_model: Vec<String> = r
        .models
        .iter()
        .map(|m| format!("{} {:.0}", m.kind.name(), m.rk4_ns))
        .collect();
    println!(
        "RK4 step, one body, per model (ns, the paper's plate): {}",
        per_model.join(", ")
    );
    println!(
        "RK4 body-steps/s, one thread, f64     {:>9.0}",
        p.body_steps_per_second_per_thread
    );
    println!(
        "RK4 body-steps/s, {} threads           {:>9.0}",
        p.threads, p.body_steps_per_second_all_cores
    );
    println!(
        "bodies in real time at 240 Hz         {:>9}   {:>7.0} *    {:.1} x",
        p.bodies_realtime,
        paper::BODIES_REALTIME,
        p.bodies_realtime as f64 / paper::BODIES_REALTIME
    );
    match &r.fit_seconds {
        Ok(s) => println!(
            "omniad fit, 13 takes, 3 iterations    {:>9.2} s    {:>7.0} s    1/{:.0}",
            s,
            paper::FIT_SECONDS,
            paper::FIT_SECONDS / s
        ),
        Err(e) => println!("omniad fit: not measured ({e})"),
    }
    match &r.peer {
        Ok(m) => println!(
            "MuJoCo {} ellipsoid fluid, RK4, one thread: {:.0} body-steps/s (Euler {:.0}); ours / MuJoCo (RK4) = {:.1} x",
            m.version,
            m.body_steps_per_second,
            m.euler_body_steps_per_second,
            p.body_steps_per_second_per_thread / m.body_steps_per_second
        ),
        Err(e) => println!("MuJoCo peer: not measured ({e})"),
    }
    match &r.tui {
        Ok(t) => println!(
            "TUI simulation view, {} bodies, {}x{} cells: {:.1} ms/frame (physics {:.1}, drawing {:.1}; worst {:.1}) = {:.0} fps",
            t.bench.bodies,
            t.bench.size.0,
            t.bench.size.1,
            t.frame_ms,
            t.physics_ms,
            t.draw_ms,
            t.worst_frame_ms,
            t.fps()
        ),
        Err(e) => println!("TUI frames: not measured ({e})"),
    }
    println!("* the paper: 1,000 bodies at about 30 fps including rendering (its step rate is not given)");
}
