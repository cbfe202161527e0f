#!/usr/bin/env bash
# kinscene set-up: installs everything the C++ backends need, idempotently.
#
#   Debian packages : libompl-dev (OMPL 1.5, boost 1.74), libeigen3-dev, pkg-config,
#                     coq (8.16, checks proofs/)
#   Python wheels   : pinned in scripts/requirements.txt, into the project-local venv .deps/venv
#                     (libpinocchio + cmeel prefix, casadi + IPOPT plugin)
#   With --bench      : the IK bench's baseline (pink, pin, qpsolvers, Clarabel), pinned in
#                     scripts/bench-requirements.txt, into .deps/bench-venv
#
# Re-running it does nothing when everything is in place. Nothing outside .deps/ and the
# Debian packages is touched; build scripts find .deps/ on their own (no exports needed).
# Set KINSCENE_SKIP_APT=1 to skip the Debian step (e.g. when you installed them otherwise).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
cd "$root"

log() { printf 'setup: %s\n' "$*" >&2; }

apt_packages=(libompl-dev libeigen3-dev pkg-config coq)
if [ "${KINSCENE_SKIP_APT:-0}" != 1 ]; then
    missing=()
    for p in "${apt_packages[@]}"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
    done
    if [ "${#missing[@]}" -gt 0 ]; then
        sudo=""
        [ "$(id -u)" -eq 0 ] || sudo="sudo"
        log "installing Debian packages: ${missing[*]}"
        $sudo apt-get update -qq
        DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
    fi
fi

venv="$root/.deps/venv"
stamp="$venv/.kinscene-requirements"
if [ ! -x "$venv/bin/python" ]; then
    log "creating $venv"
    python3 -m venv "$venv"
fi
if ! cmp -s scripts/requirements.txt "$stamp"; then
    log "installing pinned wheels (scripts/requirements.txt) into $venv"
    "$venv/bin/pip" install --quiet --disable-pip-version-check --no-deps -r scripts/requirements.txt
    cp scripts/requirements.txt "$stamp"
fi
# --- IK bench baseline (benches/ik.rs) ------------------------------------------------------
# pink (Python Pinocchio + QP IK), Pinocchio's Python bindings and qpsolvers/Clarabel, pinned in
# scripts/bench-requirements.txt, in their own venv .deps/bench-venv: apart from .deps/venv,
# whose libpinocchio wheel the build compiles against. Optional: if the install fails, the IK
# bench reports kinscene's figures and says why pink did not run. Only with `--bench` (the
# README's bench command): building and testing never need it.
if [ "${1:-}" = "--bench" ] && [ "${KINSCENE_SKIP_BENCH_VENV:-0}" != 1 ]; then
    bench_venv="$root/.deps/bench-venv"
    bench_stamp="$bench_venv/.kinscene-requirements"
    if ! cmp -s scripts/bench-requirements.txt "$bench_stamp"; then
        log "installing the IK bench baseline (scripts/bench-requirements.txt) into $bench_venv"
        if { [ -x "$bench_venv/bin/python" ] || python3 -m venv "$bench_venv"; } &&
            "$bench_venv/bin/pip" install --quiet --disable-pip-version-check \
                -r scripts/bench-requirements.txt; then
            cp scripts/bench-requirements.txt "$bench_stamp"
        else
            log "warning: bench venv not installed; benches/ik.rs will run without pink"
        fi
    fi
fi
# --- end IK bench baseline -------------------------------------------------------------------
log "ready (OMPL from Debian, Pinocchio and CasADi from $venv)"
