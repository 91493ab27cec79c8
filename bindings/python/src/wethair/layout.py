"""``python -m wethair.layout`` prints every mirrored struct's size and field offsets, one per
line, for ``bindings/check_layout.sh`` to compare with the C header's."""

from ._structs import layout_lines

if __name__ == "__main__":
    print("\n".join(layout_lines()))
