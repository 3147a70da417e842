//! The one parallelism type of the workspace, chosen by the caller.
//!
//! [`Par::Seq`] runs on the calling thread; `Par::rayon(n)` asks for rayon
//! with `n` threads (`Par::rayon(0)`: as many as rayon's current pool has).

pub use faer::Par;

/// Number of threads `par` asks for (1 for [`Par::Seq`]).
pub fn thread_count(par: Par) -> usize {
    match par {
        Par::Seq => 1,
        Par::Rayon(n) => n.get(),
    }
}

/// Whether `par` asks for more than the calling thread.
pub fn is_parallel(par: Par) -> bool {
    matches!(par, Par::Rayon(_))
}

/// Runs `f` at parallelism `par`: on the calling thread for [`Par::Seq`]; for
/// `Par::Rayon(n)` in rayon's current pool when it has `n` threads (no new
/// pool, no thread start-up), else in a new pool of `n` threads. Rayon
/// parallel iterators inside `f` then spread over that pool.
///
/// If the pool cannot be built (the system refuses threads), `f` runs in the
/// current pool: the results do not depend on the number of threads.
pub fn run_at<R: Send>(par: Par, f: impl FnOnce() -> R + Send) -> R {
    match par {
        Par::Seq => f(),
        Par::Rayon(n) if n.get() == rayon::current_num_threads() => f(),
        Par::Rayon(n) => match rayon::ThreadPoolBuilder::new().num_threads(n.get()).build() {
            Ok(pool) => pool.install(f),
            Err(_) => f(),
        },
    }
}

/// `f(0), …, f(n − 1)` collected in order, at parallelism `par`: on the
/// calling thread for [`Par::Seq`] (not rayon's global pool), else over
/// the pool [`run_at`] picks.
pub fn map_at<R, C>(par: Par, n: usize, f: impl Fn(usize) -> R + Sync + Send) -> C
where
    R: Send,
    C: FromIterator<R> + rayon::iter::FromParallelIterator<R> + Send,
{
    use rayon::prelude::*;
    if is_parallel(par) {
        run_at(par, || (0..n).into_par_iter().map(f).collect())
    } else {
        (0..n).map(f).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_in_a_pool_of_the_requested_size() {
        assert_eq!(run_at(Par::Seq, || 7), 7);
        assert_eq!(run_at(Par::rayon(3), rayon::current_num_threads), 3);
        let current = rayon::current_num_threads();
        assert_eq!(run_at(Par::rayon(0), rayon::current_num_threads), current);
        assert_eq!(thread_count(Par::Seq), 1);
        assert_eq!(thread_count(Par::rayon(2)), 2);
        assert!(is_parallel(Par::rayon(1)) && !is_parallel(Par::Seq));
    }

    #[test]
    fn map_at_keeps_the_order_whatever_the_parallelism() {
        let square = |k: usize| k * k;
        let seq: Vec<usize> = map_at(Par::Seq, 1000, square);
        let par: Vec<usize> = map_at(Par::rayon(3), 1000, square);
        assert_eq!(seq, par);
        assert_eq!(seq[999], 998_001);
        let failed: Result<Vec<usize>, usize> =
            map_at(Par::rayon(2), 10, |k| if k == 7 { Err(k) } else { Ok(k) });
        assert_eq!(failed, Err(7));
    }
}
