//! Axis ranges and tick positions.

/// A closed interval `[lo, hi]` with `lo < hi`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    /// Lower end.
    pub lo: f64,
    /// Upper end.
    pub hi: f64,
}

impl Range {
    /// The range of the finite values, widened to a unit interval around a
    /// single value and to `[0, 1]` when there is none.
    pub fn of(values: impl Iterator<Item = f64>) -> Self {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for v in values.filter(|v| v.is_finite()) {
            lo = lo.min(v);
            hi = hi.max(v);
        }
        if lo > hi {
            return Self { lo: 0.0, hi: 1.0 };
        }
        if hi - lo <= f64::EPSILON * hi.abs().max(1.0) {
            return Self {
                lo: lo - 0.5,
                hi: hi + 0.5,
            };
        }
        Self { lo, hi }
    }

    /// Maps `v` in this range to `[a, b]`.
    pub fn map(&self, v: f64, a: f64, b: f64) -> f64 {
        a + (v - self.lo) / (self.hi - self.lo) * (b - a)
    }
}

/// Most ticks [`nice_ticks`] gives; beyond it (a range whose width
/// overflows, or is lost in rounding) the ticks are the range's two ends.
const MAX_TICKS: f64 = 100.0;

/// About `count` ticks at 1, 2 or 5 times a power of ten covering `r`;
/// returns the widened range and the tick values. A range no round step
/// can cover in at most [`MAX_TICKS`] ticks (values near `f64::MAX`) keeps
/// its ends as the only ticks.
pub fn nice_ticks(r: Range, count: usize) -> (Range, Vec<f64>) {
    let ends = (r, vec![r.lo, r.hi]);
    let raw = (r.hi - r.lo) / count.max(1) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let lo = (r.lo / step).floor() * step;
    let hi = (r.hi / step).ceil() * step;
    let n = ((hi - lo) / step).round();
    if !(lo.is_finite() && hi.is_finite() && step > 0.0 && n.is_finite() && n <= MAX_TICKS) {
        return ends;
    }
    let ticks = (0..=n as usize).map(|i| lo + i as f64 * step).collect();
    (Range { lo, hi }, ticks)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_and_cover_the_range() {
        let (r, t) = nice_ticks(Range { lo: 0.3, hi: 9.2 }, 5);
        assert_eq!((r.lo, r.hi), (0.0, 10.0));
        assert_eq!(t, vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]);
        let (r, _) = nice_ticks(
            Range {
                lo: -1234.0,
                hi: 5678.0,
            },
            6,
        );
        assert!(r.lo <= -1234.0 && r.hi >= 5678.0);
    }

    /// A range whose width overflows `f64` (a coefficient file of 1e308s
    /// plotted) gave a tick count past any allocation: it keeps its ends.
    #[test]
    fn ranges_near_the_largest_float_keep_their_ends() {
        for (lo, hi) in [(-1e308, 1e308), (-f64::MAX, f64::MAX), (1.0, 1.0 + 1e-15)] {
            let (r, t) = nice_ticks(Range { lo, hi }, 5);
            assert!(t.len() <= 101, "{lo} {hi}: {} ticks", t.len());
            assert!(t.iter().all(|v| v.is_finite()), "{t:?}");
            assert!(r.lo <= lo && r.hi >= hi);
        }
        let wide = Range::of([-1e308, 1e308].into_iter());
        let (_, t) = nice_ticks(wide, 6);
        assert_eq!(t, vec![-1e308, 1e308]);
    }

    #[test]
    fn degenerate_ranges_are_widened() {
        assert_eq!(
            Range::of([2.0, 2.0].into_iter()),
            Range { lo: 1.5, hi: 2.5 }
        );
        assert_eq!(
            Range::of([f64::NAN].into_iter()),
            Range { lo: 0.0, hi: 1.0 }
        );
    }
}
