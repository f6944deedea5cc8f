//! What a speed figure was measured on: the CPU, and the vector extensions the code was built
//! to use (`target-cpu`, set in `.cargo/config.toml`), since both change the figure.

/// The CPU's name as Linux reports it (`/proc/cpuinfo`); `None` elsewhere.
pub fn cpu_name() -> Option<String> {
    let info = std::fs::read_to_string("/proc/cpuinfo").ok()?;
    info.lines().find_map(|l| Some(l.strip_prefix("model name")?.split_once(':')?.1.trim().to_string()))
}

/// The architecture and the vector extensions this build may use, e.g. `x86_64 with sse4.2,
/// avx, avx2, fma`.
pub fn code_for() -> String {
    let on = [
        ("sse4.2", cfg!(target_feature = "sse4.2")),
        ("avx", cfg!(target_feature = "avx")),
        ("avx2", cfg!(target_feature = "avx2")),
        ("fma", cfg!(target_feature = "fma")),
        ("avx512f", cfg!(target_feature = "avx512f")),
        ("neon", cfg!(target_feature = "neon")),
        ("simd128", cfg!(target_feature = "simd128")),
    ];
    let names: Vec<&str> = on.iter().filter(|(_, on)| *on).map(|(name, _)| *name).collect();
    match names.is_empty() {
        true => format!("{} (baseline instructions only)", std::env::consts::ARCH),
        false => format!("{} with {}", std::env::consts::ARCH, names.join(", ")),
    }
}
