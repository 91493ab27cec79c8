//! The C ABI: `wethair_*` functions over opaque `WetHairGroom` / `WetHairSim` handles.
//!
//! Conventions (the header repeats them):
//! - every fallible call returns a [`WetHairResult`]; on failure it writes no output, and
//!   `wethair_last_error_message()` (per thread) says what was wrong;
//! - every pointer is checked for NULL, every count against its capacity, every float for
//!   NaN, inf and sign, every enum arriving from C as a `uint32_t` against its known values;
//! - sized structs start with `struct_size`, set by their `..._default()` function (or the
//!   host, for outputs); every size from the struct's first released layout to today's is
//!   accepted (`sizes.rs`: older hosts' missing fields take their defaults, outputs are
//!   written up to the host's size), anything else is `WETHAIR_ERROR_STRUCT_SIZE`;
//! - no panic crosses the boundary: each body runs under `catch_unwind` and a panic becomes
//!   `WETHAIR_ERROR_PANIC` (the object involved should then be destroyed);
//! - thread safety: different handles may be used from different threads at once; calls on
//!   one handle must not overlap. The simulation runs its step on its own worker threads.

#[macro_use]
mod boundary;
mod enums;
mod groom;
mod meta;
mod sim;
mod sizes;
mod types;
mod unity;
mod vulkan;
mod wet;

pub use boundary::WetHairResult;
pub use enums::c_enum_constants;
pub use groom::*;
pub use meta::*;
pub use sim::*;
pub use sizes::struct_sizes;
pub use types::*;
pub use unity::*;
pub use vulkan::*;
pub use wet::*;
