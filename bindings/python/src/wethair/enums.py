"""The C header's enums as Python ``IntEnum``s (values equal the header's; a test parses the
header to hold them so). Wherever the API takes one, it also takes the member's name as a
string, in any case: ``backend="cpu"``."""

import enum


class Result(enum.IntEnum):
    """``WetHairResult``: what a C call returned."""

    OK = 0
    ERROR_NULL_POINTER = 1
    ERROR_INVALID_ARGUMENT = 2
    ERROR_STRUCT_SIZE = 3
    ERROR_CAPACITY = 4
    ERROR_BUFFER_TOO_SMALL = 5
    ERROR_IO = 6
    ERROR_PARSE = 7
    ERROR_UNSTABLE = 8
    ERROR_PANIC = 9
    ERROR_DEVICE = 10
    ERROR_UNSUPPORTED = 11


class DampingModel(enum.IntEnum):
    """``WetHairDampingModel``."""

    RELATIVE = 0
    AXIAL = 1


class ColliderShape(enum.IntEnum):
    """``WetHairColliderType``."""

    SPHERE = 0
    CAPSULE = 1


class GuideChoice(enum.IntEnum):
    """``WetHairGuideChoice``: which strands are simulated as guides."""

    ALL = 0
    EVERY_NTH = 1
    SPREAD = 2
    GIVEN = 3
    CLUSTER = 4


class VertexAttribute(enum.IntFlag):
    """``WetHairVertexAttribute``: what each output vertex holds."""

    POSITION = 1
    TANGENT = 2
    WETNESS = 4


class Integrator(enum.IntEnum):
    """``WetHairIntegrator``."""

    SYMPLECTIC_EULER = 0
    IMPLICIT_EULER = 1
    XPBD = 2
    AUTO = 3
    BDF2 = 4


class Backend(enum.IntEnum):
    """``WetHairBackend``."""

    AUTO = 0
    CPU = 1
    GPU = 2


class Readback(enum.IntEnum):
    """``WetHairReadback``."""

    LATEST = 0
    PREVIOUS_FRAME = 1


class UpAxis(enum.IntEnum):
    """``WetHairUpAxis``: how a loaded groom's axes are brought to wethair's z up."""

    KEEP = 0
    Y_TO_Z = 1


class SpringModel(enum.IntEnum):
    """``WetHairSpringModel``."""

    PER_SPRING = 0
    MATERIAL = 1


#: The header's name prefix of each enum's constants (for the test that parses the header).
HEADER_PREFIX = {
    Result: "WETHAIR_",
    DampingModel: "WETHAIR_DAMPING_",
    ColliderShape: "WETHAIR_COLLIDER_",
    GuideChoice: "WETHAIR_GUIDES_",
    VertexAttribute: "WETHAIR_ATTRIBUTE_",
    Integrator: "WETHAIR_INTEGRATOR_",
    Backend: "WETHAIR_BACKEND_",
    Readback: "WETHAIR_READBACK_",
    UpAxis: "WETHAIR_UP_AXIS_",
    SpringModel: "WETHAIR_SPRING_MODEL_",
}


def coerce(kind, value):
    """``value`` as a member of ``kind``: a member, its integer value, or its name (any case).

    Raises ``ValueError`` naming the allowed names otherwise."""
    if isinstance(value, str):
        try:
            return kind[value.upper()]
        except KeyError:
            names = ", ".join(m.name.lower() for m in kind)
            raise ValueError(f"{kind.__name__}: unknown name {value!r} (one of {names})") from None
    return kind(value)
