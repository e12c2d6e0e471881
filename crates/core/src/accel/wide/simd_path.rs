//! Which instruction set the wide walks run on: chosen once per process from what the CPU
//! has, optionally narrowed by the `LUMIS_SIMD` environment variable (`scalar`, `avx2`,
//! `avx512`), or forced by tests. Every path gives the same hits, bit for bit (each computes
//! the scalar slab test's roundings lane by lane, see [`super::child_test`]), so the choice is
//! one of speed only; tests walk every path the CPU supports.

use std::sync::atomic::{AtomicU8, Ordering};

/// An instruction set the wide walks can run on, narrowest first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum SimdPath {
    /// One child box at a time, the scalar slab test: every CPU.
    Scalar,
    /// The 8 child boxes of a node in one AVX2 register (with BMI1/2, LZCNT and POPCNT).
    Avx2,
    /// The AVX2 walk with AVX-512 (F, VL) mask compares and compressed child ordering, and
    /// the whole walk compiled with 32 vector registers.
    Avx512,
}

/// 0: not yet chosen; otherwise `1 +` the path's index in [`SimdPath::ALL`].
static CHOSEN: AtomicU8 = AtomicU8::new(0);

impl SimdPath {
    /// Every path, narrowest first.
    pub const ALL: [SimdPath; 3] = [SimdPath::Scalar, SimdPath::Avx2, SimdPath::Avx512];

    /// The name `LUMIS_SIMD` takes.
    pub fn name(self) -> &'static str {
        match self {
            SimdPath::Scalar => "scalar",
            SimdPath::Avx2 => "avx2",
            SimdPath::Avx512 => "avx512",
        }
    }

    /// The path named `name` (as [`SimdPath::name`] gives it).
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|p| p.name() == name)
    }

    /// Whether the running CPU can take this path.
    pub fn supported(self) -> bool {
        match self {
            SimdPath::Scalar => true,
            #[cfg(target_arch = "x86_64")]
            SimdPath::Avx2 => {
                std::arch::is_x86_feature_detected!("avx2")
                    && std::arch::is_x86_feature_detected!("bmi1")
                    && std::arch::is_x86_feature_detected!("bmi2")
                    && std::arch::is_x86_feature_detected!("lzcnt")
                    && std::arch::is_x86_feature_detected!("popcnt")
            }
            #[cfg(target_arch = "x86_64")]
            SimdPath::Avx512 => {
                SimdPath::Avx2.supported()
                    && std::arch::is_x86_feature_detected!("avx512f")
                    && std::arch::is_x86_feature_detected!("avx512vl")
            }
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }

    /// The paths the running CPU can take, narrowest first (for tests that walk each).
    pub fn all_supported() -> Vec<SimdPath> {
        Self::ALL.into_iter().filter(|p| p.supported()).collect()
    }

    /// The path the walks take: the widest the CPU supports, or `LUMIS_SIMD`'s if it names
    /// a supported one (read once, at the first query). An unknown or unsupported name is
    /// reported on standard error once and the widest supported path is taken.
    #[inline(always)]
    pub fn active() -> SimdPath {
        match CHOSEN.load(Ordering::Relaxed) {
            1 => SimdPath::Scalar,
            2 => SimdPath::Avx2,
            3 => SimdPath::Avx512,
            _ => Self::choose(),
        }
    }

    #[cold]
    fn choose() -> SimdPath {
        let widest = Self::ALL
            .into_iter()
            .rev()
            .find(|p| p.supported())
            .unwrap_or(SimdPath::Scalar);
        let path = match std::env::var("LUMIS_SIMD") {
            Err(_) => widest,
            Ok(name) => match Self::from_name(name.trim()) {
                Some(p) if p.supported() => p,
                _ => {
                    eprintln!(
                        "lumis: LUMIS_SIMD={name:?} is not one of scalar, avx2, avx512 that \
                         this CPU supports; using {}",
                        widest.name()
                    );
                    widest
                }
            },
        };
        // Two threads choosing at once choose the same.
        CHOSEN.store(path.index(), Ordering::Relaxed);
        path
    }

    fn index(self) -> u8 {
        match self {
            SimdPath::Scalar => 1,
            SimdPath::Avx2 => 2,
            SimdPath::Avx512 => 3,
        }
    }

    /// Makes every walk from now on take this path, for every thread (tests comparing the
    /// paths; `LUMIS_SIMD` is the user's knob). Queries under way may finish on the previous
    /// path, which gives the same answers. Refused when the CPU lacks the path.
    #[doc(hidden)]
    pub fn force(self) -> Result<(), String> {
        if !self.supported() {
            return Err(format!("this CPU cannot take the {} path", self.name()));
        }
        CHOSEN.store(self.index(), Ordering::Relaxed);
        Ok(())
    }
}
