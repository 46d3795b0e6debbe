//! Flush-to-zero and denormals-are-zero for the calling thread.
//!
//! Embree asks for both on every thread that traces: denormal arithmetic takes
//! a slow path on x86. `_mm_setcsr` is deprecated, so MXCSR is written with
//! `ldmxcsr` directly.

/// MXCSR bits: FTZ (bit 15) and DAZ (bit 6).
#[cfg(target_arch = "x86_64")]
const FTZ_DAZ: u32 = (1 << 15) | (1 << 6);

/// Sets FTZ and DAZ on the calling thread. Idempotent.
#[cfg(target_arch = "x86_64")]
pub fn enable_flush_to_zero() {
    let mut csr: u32 = 0;
    // SAFETY: stmxcsr writes 4 bytes to the address of a live local u32.
    unsafe {
        std::arch::asm!("stmxcsr [{}]", in(reg) &mut csr, options(nostack, preserves_flags));
    }
    csr |= FTZ_DAZ;
    // SAFETY: ldmxcsr reads 4 bytes from a live local; setting FTZ/DAZ only changes how
    // denormals round, it cannot unmask exceptions.
    unsafe {
        std::arch::asm!("ldmxcsr [{}]", in(reg) &csr, options(nostack, readonly, preserves_flags));
    }
}

/// Other architectures: nothing to do (Embree's ARM port handles it itself).
#[cfg(not(target_arch = "x86_64"))]
pub fn enable_flush_to_zero() {}

/// Whether FTZ and DAZ are both set on the calling thread.
#[cfg(all(test, target_arch = "x86_64"))]
fn flush_to_zero_enabled() -> bool {
    let mut csr: u32 = 0;
    // SAFETY: as in `enable_flush_to_zero`.
    unsafe {
        std::arch::asm!("stmxcsr [{}]", in(reg) &mut csr, options(nostack, preserves_flags));
    }
    csr & FTZ_DAZ == FTZ_DAZ
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::*;

    #[test]
    fn denormals_flush_after_enable() {
        std::thread::spawn(|| {
            enable_flush_to_zero();
            assert!(flush_to_zero_enabled());
            // A denormal input reads as zero under DAZ.
            let tiny = std::hint::black_box(f32::MIN_POSITIVE / 4.0);
            assert_eq!(std::hint::black_box(tiny * 1.0), 0.0);
        })
        .join()
        .unwrap();
    }
}
