//! The x86-64 SIMD code of the batch kernels: the register-backed lane types ([`lanes`]) the
//! kernels of `batch::dispatch` are instantiated for, and the copiers ([`transpose`]) that move
//! groups of contacts between the C structs and the block's rows by transposition in registers.
//! Private to `batch`: a lane value exists only inside those `#[target_feature]` kernels.

pub(crate) mod lanes;
pub(crate) mod transpose;
