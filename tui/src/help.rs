//! Every key, per view (the `?` overlay and the README use this list).

use crate::app::ViewId;

/// Keys that work everywhere.
pub const GLOBAL: &[(&str, &str)] = &[
    ("Tab / S-Tab", "next / previous view"),
    ("1 2 3 4", "sphere, kite, simulation, telemetry"),
    ("?", "this help (Esc closes)"),
    ("q Esc C-c", "quit"),
];

/// Keys of one view.
pub fn keys(view: ViewId) -> &'static [(&'static str, &'static str)] {
    match view {
        ViewId::Sphere => &[
            ("← → ↑ ↓ / drag", "rotate the sphere"),
            ("h j k l (H J K L)", "move the probe ◆ 5° (15°)"),
            ("p", "probe the direction facing you"),
            ("m / f t v", "cycle / force, torque, coverage"),
            ("a", "arrows on/off"),
            ("c / n", "compare side by side / next model"),
            ("0", "reset the view"),
        ],
        ViewId::Kite => &[
            ("↑ ↓ (k j)", "select a primitive"),
            ("a / b", "add a plate / a box"),
            ("Del Backspace", "remove the selected primitive"),
            ("m r s", "tool: move, rotate, scale"),
            ("x y z", "axis"),
            ("← → (h l)", "apply the tool along the axis (rods follow)"),
            ("( ) / [ ] / < >", "kite roll / pitch / yaw -/+ 2°"),
            ("{ }", "wind speed -/+ 0.5 m/s"),
            (", .", "attachment along the string -/+ 2 cm"),
            ("o", "optimise the design (kite optimise, small budget)"),
            ("u", "undo: the design before optimising"),
            ("w", "save the kite file"),
        ],
        ViewId::Sim => &[
            ("space / .", "run or pause / one frame"),
            ("d D", "air density ρ down / up"),
            ("s S", "size L down / up"),
            ("w W", "mass and inertia down / up"),
            ("o", "switch model: OmniAD, drag only, Fig. 12's vacuum, kirchhoff, drag-traction, simplified"),
            ("k", "tethered kite (kite view's design) in gusts"),
            ("g G / u U", "kite: gusts / wind down, up"),
            ("+ -", "double / halve the bodies"),
            ("0", "reset"),
        ],
        ViewId::Telemetry => &[
            ("space / .", "replay or pause / one frame"),
            ("← →", "seek -/+ 10 s"),
            ("Home End", "start / end"),
            ("+ -", "replay faster / slower"),
        ],
    }
}
