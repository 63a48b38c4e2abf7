//! Independent work on all cores: the takes of a set are filtered
//! independently (`crate::pipeline`), and cross-validation scores its
//! candidates independently (`crate::fit::select`).

/// `work(i, &items[i])` for every item on up to
/// [`std::thread::available_parallelism`] threads, results in index order.
pub fn map<I: Sync, T: Send>(items: &[I], work: impl Fn(usize, &I) -> T + Sync) -> Vec<T> {
    let n = items.len();
    let threads = std::thread::available_parallelism()
        .map_or(1, |p| p.get())
        .min(n);
    if threads <= 1 {
        return items.iter().enumerate().map(|(i, x)| work(i, x)).collect();
    }
    let next = std::sync::atomic::AtomicUsize::new(0);
    let mut done: Vec<(usize, T)> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                scope.spawn(|| {
                    let mut mine = Vec::new();
                    loop {
                        let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        let Some(item) = items.get(i) else {
                            break mine;
                        };
                        mine.push((i, work(i, item)));
                    }
                })
            })
            .collect();
        workers
            .into_iter()
            // A worker that panicked re-raises its panic here rather than
            // losing its items.
            .flat_map(|w| w.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
            .collect()
    });
    done.sort_by_key(|(i, _)| *i);
    done.into_iter().map(|(_, t)| t).collect()
}

#[cfg(test)]
mod tests {
    use super::map;

    #[test]
    fn map_keeps_index_order_whatever_the_threads() {
        // Uneven work so that the threads finish out of order.
        let items: Vec<usize> = (0..40).map(|i| 3 * i).collect();
        let out = map(&items, |i, x| {
            std::thread::sleep(std::time::Duration::from_micros(
                ((i * 7919) % 13) as u64 * 50,
            ));
            (i, x * x)
        });
        assert_eq!(out, (0..40).map(|i| (i, 9 * i * i)).collect::<Vec<_>>());
        assert!(map(&[] as &[usize], |_, x| *x).is_empty());
        assert_eq!(map(&[5], |i, x| i + x), vec![5]);
    }
}
