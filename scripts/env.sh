# Sourced by main.sh and test.sh after setup.sh: the environment both run in.
# Mesa's Vulkan and GL drivers print "XDG_RUNTIME_DIR is invalid or not set" on every device
# they open without a private runtime dir; give the run one (mode 0700, removed at exit).
if [ -z "${XDG_RUNTIME_DIR:-}" ] || [ ! -d "$XDG_RUNTIME_DIR" ]; then
    XDG_RUNTIME_DIR=$(mktemp -d)
    chmod 700 "$XDG_RUNTIME_DIR"
    export XDG_RUNTIME_DIR
    trap 'rm -rf "$XDG_RUNTIME_DIR"' EXIT
fi
