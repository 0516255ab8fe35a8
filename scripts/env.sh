# Environment for running shadowlab's GPU tests on a machine without a GPU (Mesa lavapipe).
# Sourced by scripts/test.sh and .ci/run; harmless on a machine with a GPU.
if [ -f /usr/share/vulkan/icd.d/lvp_icd.x86_64.json ] && [ -z "${SHADOWLAB_USE_REAL_GPU:-}" ] && ! command -v nvidia-smi >/dev/null 2>&1; then
    export VK_DRIVER_FILES=${VK_DRIVER_FILES:-/usr/share/vulkan/icd.d/lvp_icd.x86_64.json}
fi
export WGPU_BACKEND=${WGPU_BACKEND:-vulkan}
export LP_NUM_THREADS=${LP_NUM_THREADS:-2}
if [ -z "${XDG_RUNTIME_DIR:-}" ] || [ ! -d "${XDG_RUNTIME_DIR}" ]; then
    XDG_RUNTIME_DIR=$(mktemp -d)
    chmod 700 "$XDG_RUNTIME_DIR"
    export XDG_RUNTIME_DIR
fi
