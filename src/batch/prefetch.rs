//! Cache prefetch hints of the batch kernels (`PREFETCHT0` and `PREFETCHT1` on x86-64, nothing
//! elsewhere): the host's slots of the contacts ahead are touched while the kernel steps the
//! current ones (see `Gather::touch`).

/// Prefetches the cache line holding `*p` into L1 (`PREFETCHT0`; no-op off x86-64): for the
/// contacts' histories, read in order, one record or state per contact. Measured (A, 1.2M
/// contacts, full set, f64 AVX-512, records of 7 doubles): 23.3 ns per contact into L1 against
/// 25.4 into L2.
#[inline(always)]
pub(crate) fn prefetch_l1<T>(p: &T) {
    // Off x86-64 there is no hint to give.
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
    #[cfg(target_arch = "x86_64")]
    // SAFETY: PREFETCHT0 is a hint: it never faults and changes no architectural state; the
    // address comes from a live reference anyway.
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(
            (p as *const T).cast::<i8>(),
        )
    }
}

/// Prefetches the cache line holding `*p` into L2 (`PREFETCHT1`; no-op off x86-64). Measured
/// at 1M contacts with an earlier kernel: into L2 51 ns/contact, into L1 (`T0`) 69: the lines
/// of 48 contacts ahead crowd L1.
#[inline(always)]
pub(crate) fn prefetch<T>(p: &T) {
    // Off x86-64 there is no hint to give.
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
    #[cfg(target_arch = "x86_64")]
    // SAFETY: PREFETCHT1 is a hint: it never faults and changes no architectural state; the
    // address comes from a live reference anyway.
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T1 }>(
            (p as *const T).cast::<i8>(),
        )
    }
}

/// Prefetches into L2 the line holding byte `offset` of `slots[i]`, without a bounds check: the
/// address is computed with wrapping arithmetic and never dereferenced, so an index past the
/// end prefetches a line the program may not own, which is harmless. Saves the compare and
/// branch per touched slot that [`prefetch`] through a checked `get` costs (15 slots per
/// contact in the particle-major call).
#[inline(always)]
pub(crate) fn prefetch_at<T>(slots: &[T], i: usize, offset: usize) {
    let _address = slots
        .as_ptr()
        .wrapping_add(i)
        .cast::<i8>()
        .wrapping_add(offset);
    #[cfg(target_arch = "x86_64")]
    // SAFETY: PREFETCHT1 is a hint: it never faults, whatever the address, and changes no
    // architectural state; nothing is read or written through `_address`.
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T1 }>(_address)
    }
}
