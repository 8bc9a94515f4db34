//! The SIMD policy: which kernels run with which instructions, decided once per process.
//!
//! Every hand-vectorised or multiversioned kernel asks here ([`avx`], [`avx512`]) instead of
//! probing the processor itself. The processor is probed once ([`detected`]) and the answer
//! cached with the environment's choice:
//!
//! - `MAGBUBBLE_PORTABLE=1` (or `all`): every kernel takes its portable path ([`level`] is
//!   [`Level::Portable`]). CI runs the physics tests once this way.
//! - `MAGBUBBLE_PORTABLE=name,name,…` (names of [`Kernel::name`]): only those kernels take the
//!   portable path (for measuring one kernel against its portable form, docs/performance.md).
//! - unset, empty or `0`: every kernel takes the best path the processor has.
//!
//! Every SIMD kernel computes the portable kernel's operations in the same order (no FMA), so
//! the choice never changes a result bit; the tests beside each kernel compare the two.
//! A kernel stays only while it earns ≥ 5 % on the workload it was written for (the policy
//! table in docs/performance.md).

use std::sync::OnceLock;

/// The instruction sets a kernel may use, ordered: a level includes the ones below it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Level {
    /// The build's baseline (x86-64: SSE2), or any other architecture.
    Portable,
    /// AVX, AVX2 and FMA (x86-64-v3; the kernels use AVX and AVX2, never FMA).
    Avx2Fma,
    /// Avx2Fma and AVX-512F.
    Avx512,
}

impl Level {
    /// The name the tests print.
    pub fn name(self) -> &'static str {
        match self {
            Level::Portable => "portable",
            Level::Avx2Fma => "avx2-fma",
            Level::Avx512 => "avx512",
        }
    }
}

/// The kernels that have a SIMD form, each switchable to its portable form alone.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kernel {
    /// The matrix exponential's element-wise loops and Padé solve (analysis/expm.rs).
    Expm,
    /// The pair-row products of the second-order loads (model/effects/pair_rows_kernels.rs), AVX.
    PairRows,
    /// The same with AVX-512 (strides that are multiples of 8); portable here means the AVX form.
    PairRows512,
    /// The frame map's dense and sparse sweeps (model/effects/frame_sweep.rs).
    FrameSweep,
    /// The vorticity functionals' 4-lane sums (model/vorticity/operator.rs).
    VorticityFunctionals,
}

impl Kernel {
    /// Every kernel, in the order of their bits.
    pub const ALL: [Kernel; 5] = [Kernel::Expm, Kernel::PairRows, Kernel::PairRows512, Kernel::FrameSweep, Kernel::VorticityFunctionals];

    /// The name `MAGBUBBLE_PORTABLE` takes.
    pub fn name(self) -> &'static str {
        match self {
            Kernel::Expm => "expm",
            Kernel::PairRows => "pair_rows",
            Kernel::PairRows512 => "pair_rows_avx512",
            Kernel::FrameSweep => "frame_sweep",
            Kernel::VorticityFunctionals => "vorticity_functionals",
        }
    }

    #[inline]
    fn bit(self) -> u32 {
        1 << (self as u32)
    }
}

/// What the processor supports (probed once).
pub fn detected() -> Level {
    static DETECTED: OnceLock<Level> = OnceLock::new();
    *DETECTED.get_or_init(probe)
}

#[cfg(target_arch = "x86_64")]
fn probe() -> Level {
    use std::arch::is_x86_feature_detected as has;
    if !(has!("avx") && has!("avx2") && has!("fma")) {
        Level::Portable
    } else if has!("avx512f") {
        Level::Avx512
    } else {
        Level::Avx2Fma
    }
}

#[cfg(not(target_arch = "x86_64"))]
fn probe() -> Level {
    Level::Portable
}

/// The policy in force: the level and the kernels forced portable (bits of [`Kernel::bit`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Policy {
    level: Level,
    portable: u32,
}

/// `MAGBUBBLE_PORTABLE`'s value read as a policy on a processor at `hw`; an unknown kernel
/// name is an error naming it and the known ones.
fn parse(value: Option<&str>, hw: Level) -> Result<Policy, String> {
    let v = value.map(str::trim).unwrap_or("");
    match v {
        "" | "0" => return Ok(Policy { level: hw, portable: 0 }),
        "1" | "all" => return Ok(Policy { level: Level::Portable, portable: 0 }),
        _ => {}
    }
    let mut portable = 0;
    for name in v.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let k = Kernel::ALL.iter().find(|k| k.name() == name).ok_or_else(|| {
            let known: Vec<_> = Kernel::ALL.iter().map(|k| k.name()).collect();
            format!("MAGBUBBLE_PORTABLE: unknown kernel `{name}` (expected 1, all, 0 or a comma list of: {})", known.join(", "))
        })?;
        portable |= k.bit();
    }
    Ok(Policy { level: hw, portable })
}

fn policy() -> Policy {
    static POLICY: OnceLock<Policy> = OnceLock::new();
    *POLICY.get_or_init(|| {
        let value = std::env::var("MAGBUBBLE_PORTABLE").ok();
        parse(value.as_deref(), detected()).unwrap_or_else(|e| {
            // a typo must not silently measure the wrong thing: every kernel portable, said once
            eprintln!("warning: {e}; every kernel takes its portable path");
            Policy { level: Level::Portable, portable: 0 }
        })
    })
}

/// The level every kernel may use (after `MAGBUBBLE_PORTABLE=1`).
pub fn level() -> Level {
    policy().level
}

/// The kernels `MAGBUBBLE_PORTABLE` forced to their portable form (all of them when it is `1`).
pub fn portable_kernels() -> Vec<Kernel> {
    let p = policy();
    Kernel::ALL.into_iter().filter(|k| p.level == Level::Portable || p.portable & k.bit() != 0).collect()
}

/// Kernel `k` may run its AVX/AVX2 form: the processor has [`Level::Avx2Fma`] and `k` is not
/// forced portable. The check costs one load and two compares.
#[inline]
pub fn avx(k: Kernel) -> bool {
    let p = policy();
    p.level >= Level::Avx2Fma && p.portable & k.bit() == 0
}

/// Kernel `k` may run its AVX-512F form.
#[inline]
pub fn avx512(k: Kernel) -> bool {
    let p = policy();
    p.level >= Level::Avx512 && p.portable & k.bit() == 0
}

/// A test comparing a kernel's SIMD form with its portable form runs only on a processor with
/// `need`; otherwise it says so on stderr (not a silent pass) and returns false.
pub fn test_can_run(need: Level, what: &str) -> bool {
    let ok = detected() >= need;
    if !ok {
        eprintln!("SKIPPED {what}: the processor has {} (needs {})", detected().name(), need.name());
    }
    ok
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_environment_value_is_read_as_documented() {
        let hw = Level::Avx512;
        assert_eq!(parse(None, hw), Ok(Policy { level: hw, portable: 0 }));
        assert_eq!(parse(Some("0"), hw), Ok(Policy { level: hw, portable: 0 }));
        assert_eq!(parse(Some(" 1 "), hw), Ok(Policy { level: Level::Portable, portable: 0 }));
        assert_eq!(parse(Some("all"), hw), Ok(Policy { level: Level::Portable, portable: 0 }));
        let p = parse(Some("expm, pair_rows"), hw).unwrap();
        assert_eq!(p.level, hw);
        assert_eq!(p.portable, Kernel::Expm.bit() | Kernel::PairRows.bit());
        let e = parse(Some("expm,nope"), hw).unwrap_err();
        assert!(e.contains("`nope`") && e.contains("pair_rows"), "{e}");
    }

    #[test]
    fn every_kernel_has_its_own_bit_and_name() {
        let bits: Vec<u32> = Kernel::ALL.iter().map(|k| k.bit()).collect();
        for (i, b) in bits.iter().enumerate() {
            assert_eq!(*b, 1 << i);
        }
        let mut names: Vec<_> = Kernel::ALL.iter().map(|k| k.name()).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), Kernel::ALL.len());
    }
}
