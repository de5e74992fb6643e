//! Run-time CPU dispatch. The shipped library is built for the x86-64 baseline (it must load on any x86-64);
//! the function evaluation is compiled a second time for AVX2 + FMA (`Vehicle::derivative_on_avx2_fma`) and
//! used when the CPU has them. The two give the same numbers bit for bit (Rust never contracts a multiply
//! and an add into an FMA by itself; tests/multibody.rs checks it): the wider instructions change the speed,
//! not the results. `RTV_PORTABLE_EVALUATION=1` in the environment forces the baseline code.
//!
//! Under valgrind the baseline code runs too: valgrind 3.19 (Debian 12's) cannot decode every AVX
//! instruction LLVM emits here (`vmovq %xmm9,%xmm4` stops it with SIGILL). Valgrind is recognised by its
//! preloaded `vgpreload_*.so` in `LD_PRELOAD`, which every valgrind tool sets.

use std::sync::OnceLock;

/// True if the evaluation may use the AVX2 + FMA code.
#[inline]
pub fn avx2_fma() -> bool {
    static CHOICE: OnceLock<bool> = OnceLock::new();
    *CHOICE.get_or_init(|| {
        #[cfg(target_arch = "x86_64")]
        {
            let forced_portable = std::env::var_os("RTV_PORTABLE_EVALUATION").is_some_and(|v| v == "1");
            let under_valgrind =
                std::env::var_os("LD_PRELOAD").is_some_and(|v| v.to_string_lossy().contains("vgpreload"));
            !forced_portable
                && !under_valgrind
                && std::arch::is_x86_feature_detected!("avx2")
                && std::arch::is_x86_feature_detected!("fma")
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            false
        }
    })
}
