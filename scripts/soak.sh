#!/usr/bin/env bash
# The viewer's soak (`make soak`): FRAMES frames (default 10000) under Xvfb at a small size, the
# swapchain re-created every 47 frames (--inject-out-of-date), resident memory and meadow's count
# of live Vulkan objects (`vk::live`) sampled every tenth of the run. Without validation it fails
# on RSS growth above 4 MiB or any growth of live objects between the second sample (after
# warm-up) and the last; then it reports the same figures with validation on (the layer keeps
# memory of its own). Extra arguments go to `meadow view` (e.g. --brute-force).
set -euo pipefail
frames=${FRAMES:-10000}
# Samples every tenth of the run, rounded to 50 frames. A retired swapchain stays queued for a few
# completed frames after each re-creation, and how many frames have completed by then depends on
# the GPU's pace, so a sample must not fall just after one: with re-creations every 47 frames, the
# second and the last sample of a 1 000- or 10 000-frame run fall 12 to 36 frames after the last
# re-creation (with a period of 50 they fell on it, and a slow frame, the fluid wind's, counted
# one object more or less).
every=$(( (frames / 10 + 49) / 50 * 50 ))
meadow=${MEADOW:-target/release/meadow}
# The soaks run on the lavapipe profile (`vk::profile`), whatever the environment says: its rule
# (a value that decides control flow is read through storage) is what keeps lavapipe's memory flat.
export MEADOW_PROFILE=lavapipe
# The viewer under an Xvfb of its own (not xvfb-run, which at exit can replace the viewer's
# status with its own when it fails to remove its temporary folder). -displayfd picks a free
# display and writes its number once the server accepts clients.
run() {
    local ready server status=0
    ready=$(mktemp)
    Xvfb -displayfd 3 -screen 0 640x480x24 -nolisten tcp -noreset 3>"$ready" 2>/dev/null &
    server=$!
    until [[ -s $ready ]]; do
        if ! kill -0 "$server" 2>/dev/null; then
            echo "soak: Xvfb did not start" >&2
            rm -f "$ready"
            return 1
        fi
        sleep 0.1
    done
    DISPLAY=":$(<"$ready")" "$meadow" view --blades 2000 --size 96x64 --frames "$frames" \
        --inject-out-of-date 47 --sample-every "$every" "$@" | grep '^sample:' || status=$?
    kill "$server" 2>/dev/null
    wait "$server" 2>/dev/null || true
    rm -f "$ready"
    return "$status"
}
# sample: frame F rss_kib R live_vulkan_objects L  ->  "F R L"
fields() { awk '{print $3, $5, $7}'; }
check() {
    local label=$1 samples=$2
    # A viewer that failed, or printed too few samples, fails the soak: no samples is no evidence.
    if (( $(grep -c '^sample:' <<<"$samples") < 2 )); then
        echo "soak ($label): the viewer printed fewer than 2 samples"
        return 1
    fi
    read -r f0 r0 l0 <<<"$(sed -n 2p <<<"$samples" | fields)"
    read -r f1 r1 l1 <<<"$(tail -n 1 <<<"$samples" | fields)"
    echo "soak ($label): frames $f0 -> $f1: RSS $r0 -> $r1 KiB ($((r1 - r0)) KiB), live Vulkan objects $l0 -> $l1"
    [[ $label == validation ]] && return 0  # the layer keeps memory of its own: reported only
    if (( r1 - r0 > 4096 )); then echo "soak: RSS grew by $((r1 - r0)) KiB (> 4096)"; return 1; fi
    if (( l1 != l0 )); then
        echo "soak: live Vulkan objects grew from $l0 to $l1"
        # By type (the viewer's `by_type` field), to name what changed.
        echo "soak: frame $f0: $(sed -n 2p <<<"$samples" | awk '{print $9}')"
        echo "soak: frame $f1: $(tail -n 1 <<<"$samples" | awk '{print $9}')"
        return 1
    fi
}
status=0
# `run` failing (the viewer's exit status, through pipefail) fails the soak.
plain=$(run "$@") || { echo "soak (plain): the viewer failed or printed no samples"; exit 1; }
check plain "$plain" || status=1
with_validation=$(run --validation "$@") || { echo "soak (validation): the viewer failed or printed no samples"; exit 1; }
check validation "$with_validation" || status=1
exit $status
