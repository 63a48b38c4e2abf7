//! The kite file's `[[rod]]` tables as a designer reads them, for the
//! TOML that `kite optimise -o` and the TUI's save write
//! ([`crate::spec::KiteSpec::to_toml`]).
//!
//! Why not `toml::to_string` alone: it writes each rod end, a struct in
//! an array of tables, as its own `[rod.from]` / `[rod.to]` sub-table, so
//! one rod takes eight lines and its two ends are no longer read side by
//! side. The bundled files write `from = { primitive = "front", corner =
//! "+x+y-z" }`; so does this: the spec without its rods is serialised as
//! before, then each `[[rod]]` is appended with its ends as inline tables
//! (an old-style end as an inline array of three numbers).

use crate::rod_end::RodEnd;
use anyhow::Result;
use std::fmt::Write;

/// Appends one `[[rod]]` table (ends `from`, `to`; `diameter` when
/// given) to `text`.
pub fn write_rod(
    text: &mut String,
    from: &RodEnd,
    to: &RodEnd,
    diameter: Option<f64>,
) -> Result<()> {
    // `toml::Value`'s Display writes a value as it appears after `key = `:
    // tables inline, arrays on one line, strings quoted and escaped.
    let from = toml::Value::try_from(from)?;
    let to = toml::Value::try_from(to)?;
    write!(text, "\n[[rod]]\nfrom = {from}\nto = {to}\n")?;
    if let Some(d) = diameter {
        writeln!(text, "diameter = {}", toml::Value::Float(d))?;
    }
    Ok(())
}
