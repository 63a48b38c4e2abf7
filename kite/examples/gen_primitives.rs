//! Regenerates the KiteShop primitive library:
//! `cargo run --release -p omniad-kite --example gen_primitives -- data/primitives`.

fn main() -> anyhow::Result<()> {
    let dir = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "data/primitives".into());
    omniad_kite::generate::write_library(std::path::Path::new(&dir))?;
    println!("wrote the primitive library to {dir}");
    Ok(())
}
