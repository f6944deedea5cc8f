//! Timing for the benches: this thread's CPU time where Linux reports it (the machine is
//! shared), medians over batches after a warm-up. The clock is `clock_gettime`'s thread CPU
//! clock, which counts to the nanosecond (`/proc/thread-self/schedstat`, read before, advanced
//! only at scheduler ticks: 4 ms steps on some VMs, 1 % of a bench pass).

use std::time::Instant;

use anyhow::Result;

/// Calls before timing starts.
const WARMUP: usize = 20;

/// This thread's CPU time (Linux), or wall-clock time elsewhere.
pub enum Clock {
    Cpu(u64),
    Wall(Instant),
}

impl Clock {
    #[cfg(target_os = "linux")]
    pub fn cpu_ns() -> Option<u64> {
        let t = rustix::time::clock_gettime(rustix::time::ClockId::ThreadCPUTime);
        Some(u64::try_from(t.tv_sec).ok()? * 1_000_000_000 + u64::try_from(t.tv_nsec).ok()?)
    }

    #[cfg(not(target_os = "linux"))]
    pub fn cpu_ns() -> Option<u64> {
        None
    }

    pub fn now() -> Clock {
        Clock::cpu_ns().map_or_else(|| Clock::Wall(Instant::now()), Clock::Cpu)
    }

    pub fn elapsed_ms(&self) -> f64 {
        match self {
            Clock::Cpu(start) => Clock::cpu_ns().map_or(f64::NAN, |now| now.saturating_sub(*start) as f64 * 1e-6),
            Clock::Wall(start) => start.elapsed().as_secs_f64() * 1e3,
        }
    }
}

/// Median over `batches` of the mean time of one call of `work`. Each batch runs about
/// `batch_ms`, so that one interruption is a small error; the first, calibrating batch is the
/// warm-up.
pub fn median_ms(batches: usize, batch_ms: f64, mut work: impl FnMut() -> Result<()>) -> Result<f64> {
    let clock = Clock::now();
    let mut calls = 0usize;
    while calls < WARMUP || clock.elapsed_ms() < batch_ms / 2.0 {
        work()?;
        calls += 1;
    }
    let per_batch = ((calls as f64 * batch_ms / clock.elapsed_ms().max(1e-3)) as usize).max(1);
    let mut times = Vec::with_capacity(batches);
    for _ in 0..batches {
        let clock = Clock::now();
        for _ in 0..per_batch {
            work()?;
        }
        times.push(clock.elapsed_ms() / per_batch as f64);
    }
    times.sort_by(f64::total_cmp);
    Ok(times[times.len() / 2])
}

/// Median over `passes` of the mean time of `work(k)`, called for `k` in `0..n` in order in
/// each pass, after one warm-up pass: for work whose cost depends on what came before it (a
/// camera's static layer), each pass is one whole sequence.
pub fn median_pass_ms(passes: usize, n: usize, mut work: impl FnMut(usize) -> Result<()>) -> Result<f64> {
    let n = n.max(1);
    for k in 0..n {
        work(k)?;
    }
    let mut times = Vec::with_capacity(passes.max(1));
    for _ in 0..passes.max(1) {
        let clock = Clock::now();
        for k in 0..n {
            work(k)?;
        }
        times.push(clock.elapsed_ms() / n as f64);
    }
    times.sort_by(f64::total_cmp);
    Ok(times[times.len() / 2])
}
