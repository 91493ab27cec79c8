//! Flush-to-zero for the step. Hair coming to rest (damping, friction on a collider) drives
//! velocities toward zero exponentially; once they turn denormal every float operation on them
//! costs ~100 cycles, which made resting hair 2-3x slower than swinging hair. Game engines run
//! their math with denormals flushed; wethair does so inside the step only: worker threads keep
//! the mode for life, and the calling thread gets its own mode back when the guard drops.

/// Sets flush-to-zero and denormals-are-zero until dropped, then restores the previous mode.
pub struct FlushDenormals {
    #[allow(dead_code)]
    saved: u64,
}

#[cfg(target_arch = "x86_64")]
mod imp {
    // MXCSR bits: FTZ (15) and DAZ (6).
    const BITS: u32 = (1 << 15) | (1 << 6);

    pub fn enter() -> u64 {
        let mut csr: u32 = 0;
        // SAFETY: stmxcsr/ldmxcsr only read and write the SSE control register of this thread.
        unsafe {
            std::arch::asm!("stmxcsr [{}]", in(reg) &mut csr, options(nostack));
            let set = csr | BITS;
            std::arch::asm!("ldmxcsr [{}]", in(reg) &set, options(nostack));
        }
        csr as u64
    }

    pub fn leave(saved: u64) {
        let csr = saved as u32;
        // SAFETY: restores the value read in `enter` on the same thread.
        unsafe { std::arch::asm!("ldmxcsr [{}]", in(reg) &csr, options(nostack)) };
    }
}

#[cfg(target_arch = "aarch64")]
mod imp {
    // FPCR bit 24: flush-to-zero.
    pub fn enter() -> u64 {
        let fpcr: u64;
        // SAFETY: reads and writes this thread's floating-point control register only.
        unsafe {
            std::arch::asm!("mrs {}, fpcr", out(reg) fpcr, options(nomem, nostack));
            std::arch::asm!("msr fpcr, {}", in(reg) fpcr | (1 << 24), options(nomem, nostack));
        }
        fpcr
    }

    pub fn leave(saved: u64) {
        // SAFETY: restores the value read in `enter` on the same thread.
        unsafe { std::arch::asm!("msr fpcr, {}", in(reg) saved, options(nomem, nostack)) };
    }
}

#[cfg(not(any(target_arch = "x86_64", target_arch = "aarch64")))]
mod imp {
    pub fn enter() -> u64 {
        0
    }
    pub fn leave(_: u64) {}
}

impl FlushDenormals {
    /// Enters flush-to-zero on the current thread.
    pub fn new() -> Self {
        FlushDenormals { saved: imp::enter() }
    }

    /// Enters flush-to-zero on the current thread for good (pool workers).
    pub fn forever() {
        imp::enter();
    }
}

impl Default for FlushDenormals {
    fn default() -> Self {
        Self::new()
    }
}

impl Drop for FlushDenormals {
    fn drop(&mut self) {
        imp::leave(self.saved);
    }
}
