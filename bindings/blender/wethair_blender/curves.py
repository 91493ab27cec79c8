"""Between a Blender hair Curves object and arrays: point positions, curve sizes, a point
attribute."""

import numpy as np


def active_hair(context):
    """The active object when it is a hair Curves object, else None (the operators' and panel's poll)."""
    obj = context.object
    return obj if obj is not None and obj.type == "CURVES" else None


def sizes(curves) -> np.ndarray:
    """Points per curve."""
    offsets = np.zeros(len(curves.curves) + 1, dtype=np.int32)
    curves.curve_offset_data.foreach_get("value", offsets)
    return np.diff(offsets)


def positions(curves) -> np.ndarray:
    """Every point's position, object space, ``(points, 3)`` float32."""
    p = np.empty(len(curves.points) * 3, dtype=np.float32)
    curves.points.foreach_get("position", p)
    return p.reshape(-1, 3)


def set_positions(curves, p: np.ndarray) -> None:
    curves.points.foreach_set("position", np.ascontiguousarray(p, dtype=np.float32).ravel())
    curves.update_tag()


def _point_attribute(curves, name: str, data_type: str):
    """The point attribute ``name`` of ``data_type`` (made, or made again, when missing or different)."""
    attr = curves.attributes.get(name)
    if attr is None or attr.domain != "POINT" or attr.data_type != data_type:
        if attr is not None:
            curves.attributes.remove(attr)
        attr = curves.attributes.new(name, data_type, "POINT")
    return attr


def set_point_attribute(curves, name: str, values: np.ndarray) -> None:
    """A float point attribute, e.g. ``wetness`` for a material to read."""
    data = _point_attribute(curves, name, "FLOAT").data
    data.foreach_set("value", np.ascontiguousarray(values, dtype=np.float32))


def set_point_color(curves, name: str, rgba: np.ndarray) -> None:
    """A float colour point attribute (for the Workbench's Attribute colouring)."""
    data = _point_attribute(curves, name, "FLOAT_COLOR").data
    data.foreach_set("color", np.ascontiguousarray(rgba, dtype=np.float32).ravel())


def transform(m, p: np.ndarray) -> np.ndarray:
    """``p`` ``(n, 3)`` through the 4 x 4 matrix ``m`` (anything ``np.array`` takes)."""
    m = np.array(m, dtype=np.float64)
    return (p @ m[:3, :3].T + m[:3, 3]).astype(np.float32)
