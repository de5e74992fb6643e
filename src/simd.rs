//! Run-time CPU dispatch. The shipped library is built for the x86-64 baseline (it must load on any x86-64);
//! the function evaluation is compiled a second time for AVX2 + FMA (`Vehicle::derivative_on_avx2_fma`) and
//! used when the CPU has them. The two give the same numbers bit for bit (Rust never contracts a multiply
//! and an add into an FMA by itself; tests/multibody.rs checks it): the wider instructions change the speed,
//! not the results. `RTV_PORTABLE_EVALUATION=1` in the environment forces the baseline code.

use std::sync::OnceLock;

/// True if the evaluation may use the AVX2 + FMA code.
#[inline]
pub fn avx2_fma() -> bool {
    static CHOICE: OnceLock<bool> = OnceLock::new();
    *CHOICE.get_or_init(|| {
        #[cfg(target_arch = "x86_64")]
        {
            std::env::var_os("RTV_PORTABLE_EVALUATION").is_none_or(|v| v != "1")
                && std::arch::is_x86_feature_detected!("avx2")
                && std::arch::is_x86_feature_detected!("fma")
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            false
        }
    })
}
