//! A signed value as a text bar about zero (the static eigenvalues and
//! the modes' growth rates in the kite view).

/// One eigenvalue as a bar about zero: `◀====|` stable (negative, blue),
/// `|####▶` unstable (positive, red).
pub fn eigen_bar(value: f64, scale: f64, half: usize) -> String {
    let n = if scale > 0.0 {
        ((value.abs() / scale) * half as f64).ceil() as usize
    } else {
        0
    };
    let n = n.min(half);
    if value < 0.0 {
        format!(
            "{}◀{}|{}",
            " ".repeat(half - n),
            "=".repeat(n),
            " ".repeat(half + 1)
        )
    } else {
        format!(
            "{}|{}▶{}",
            " ".repeat(half + 1),
            "#".repeat(n),
            " ".repeat(half - n)
        )
    }
}
