//! The enums of the C ABI, validated once. Each enum is declared once, in Rust, `#[repr(u32)]`,
//! and cbindgen exports it (under its C name, with its constants' prefix given by a
//! `cbindgen:rename-all=prefix:` rule where the Rust name differs); structs carry them as
//! `uint32_t`. [`c_enum!`] gives each the one conversion from a C value ([`read_enum`], which
//! refuses unknown values naming the field and the type) and the C names of its constants.

use super::boundary::{Fail, WetHairResult};
use super::types::{WetHairColliderType, WetHairGuideChoice, WetHairVertexAttribute};
use crate::groom::UpAxis;
use crate::params::{Backend, Integrator, Readback, SpringModel};
use crate::physics::spring::DampingModel;

/// An enum that crosses the C ABI as a `uint32_t`.
pub(crate) trait CEnum: Copy + 'static {
    /// Its name in the header.
    const C_TYPE: &'static str;
    /// Every value, in declaration order.
    const ALL: &'static [Self];
    /// The value as C sees it.
    fn raw(self) -> u32;
    /// The constant's name in the header, NUL-terminated.
    fn c_name(self) -> &'static str;
    /// The value for `raw`, if it is one.
    fn from_raw(raw: u32) -> Option<Self> {
        Self::ALL.iter().copied().find(|v| v.raw() == raw)
    }
}

/// Implements [`CEnum`] for an enum from its C type name, its constants' prefix and its
/// variants. The generated `c_name` matches every variant, so a variant missing from the list
/// does not compile.
macro_rules! c_enum {
    ($ty:ty, $c_type:literal, $prefix:literal, [$($v:ident),+ $(,)?]) => {
        impl CEnum for $ty {
            const C_TYPE: &'static str = $c_type;
            const ALL: &'static [Self] = &[$(<$ty>::$v),+];
            fn raw(self) -> u32 {
                self as u32
            }
            fn c_name(self) -> &'static str {
                match self {
                    $(<$ty>::$v => concat!($prefix, stringify!($v), "\0"),)+
                }
            }
        }
    };
}

c_enum!(
    DampingModel,
    "WetHairDampingModel",
    "WETHAIR_DAMPING_",
    [RELATIVE, AXIAL]
);
c_enum!(
    Integrator,
    "WetHairIntegrator",
    "WETHAIR_INTEGRATOR_",
    [SYMPLECTIC_EULER, IMPLICIT_EULER, XPBD, AUTO, BDF2]
);
c_enum!(Backend, "WetHairBackend", "WETHAIR_BACKEND_", [AUTO, CPU, GPU]);
c_enum!(
    Readback,
    "WetHairReadback",
    "WETHAIR_READBACK_",
    [LATEST, PREVIOUS_FRAME]
);
c_enum!(UpAxis, "WetHairUpAxis", "WETHAIR_UP_AXIS_", [KEEP, Y_TO_Z]);
c_enum!(
    SpringModel,
    "WetHairSpringModel",
    "WETHAIR_SPRING_MODEL_",
    [PER_SPRING, MATERIAL]
);
c_enum!(
    WetHairGuideChoice,
    "WetHairGuideChoice",
    "",
    [
        WETHAIR_GUIDES_ALL,
        WETHAIR_GUIDES_EVERY_NTH,
        WETHAIR_GUIDES_SPREAD,
        WETHAIR_GUIDES_GIVEN,
        WETHAIR_GUIDES_CLUSTER
    ]
);
c_enum!(
    WetHairColliderType,
    "WetHairColliderType",
    "",
    [WETHAIR_COLLIDER_SPHERE, WETHAIR_COLLIDER_CAPSULE]
);
c_enum!(
    WetHairVertexAttribute,
    "WetHairVertexAttribute",
    "",
    [
        WETHAIR_ATTRIBUTE_POSITION,
        WETHAIR_ATTRIBUTE_TANGENT,
        WETHAIR_ATTRIBUTE_WETNESS
    ]
);
c_enum!(
    WetHairResult,
    "WetHairResult",
    "",
    [
        WETHAIR_OK,
        WETHAIR_ERROR_NULL_POINTER,
        WETHAIR_ERROR_INVALID_ARGUMENT,
        WETHAIR_ERROR_STRUCT_SIZE,
        WETHAIR_ERROR_CAPACITY,
        WETHAIR_ERROR_BUFFER_TOO_SMALL,
        WETHAIR_ERROR_IO,
        WETHAIR_ERROR_PARSE,
        WETHAIR_ERROR_UNSTABLE,
        WETHAIR_ERROR_PANIC,
        WETHAIR_ERROR_DEVICE,
        WETHAIR_ERROR_UNSUPPORTED,
    ]
);

/// The value of `field` as a `T`, or `WETHAIR_ERROR_INVALID_ARGUMENT` naming the field, the
/// value and the type.
pub(crate) fn read_enum<T: CEnum>(raw: u32, field: &str) -> Result<T, Fail> {
    T::from_raw(raw).ok_or_else(|| {
        Fail(
            WetHairResult::WETHAIR_ERROR_INVALID_ARGUMENT,
            format!("{field} {raw} is not a {}", T::C_TYPE),
        )
    })
}

/// Every C enum's constants with their values, `(type, constant, value)`: the header must
/// declare exactly these (`tests/header.rs`).
pub fn c_enum_constants() -> Vec<(&'static str, &'static str, u32)> {
    fn all<T: CEnum>(out: &mut Vec<(&'static str, &'static str, u32)>) {
        for v in T::ALL {
            out.push((T::C_TYPE, v.c_name().trim_end_matches('\0'), v.raw()));
        }
    }
    let mut out = Vec::new();
    all::<DampingModel>(&mut out);
    all::<Integrator>(&mut out);
    all::<Backend>(&mut out);
    all::<Readback>(&mut out);
    all::<UpAxis>(&mut out);
    all::<SpringModel>(&mut out);
    all::<WetHairColliderType>(&mut out);
    all::<WetHairGuideChoice>(&mut out);
    all::<WetHairVertexAttribute>(&mut out);
    all::<WetHairResult>(&mut out);
    out
}
