#!/bin/sh
# The system programs the tests run against, installed by `make test` when missing:
#   OPM Flow (Debian libopm-simulators-bin: `flow`), the independent reference of the corner-point,
#   transmissibility and simulation tests;
#   SLURM and munge (Debian slurm-wlm, munge: slurmctld, slurmd, munged), the single-node cluster
#   that tests/workflow/test_slurm.py starts (tests/slurm_cluster.py).
# `sh tests/system_tools.sh flow` installs OPM Flow alone: what `make run` needs (the sample
# study grid_choice simulates its variants).
# Needs apt-get and root (or sudo). Without them it says what to install and fails; to run the
# tests without these programs anyway, set GRIDLIB_SKIP_MISSING_TOOLS=1 (their tests then skip).
set -eu
only="${1:-all}"
missing=""
command -v flow >/dev/null 2>&1 || missing="libopm-simulators-bin"
if [ "$only" != "flow" ]; then
    for program in slurmctld slurmd munged; do
        if ! command -v "$program" >/dev/null 2>&1; then
            missing="$missing slurm-wlm munge"
            break
        fi
    done
fi
[ -z "$missing" ] && exit 0
if [ "${GRIDLIB_SKIP_MISSING_TOOLS:-}" = "1" ]; then
    echo "make: not installing $missing (GRIDLIB_SKIP_MISSING_TOOLS=1): their tests skip" >&2
    exit 0
fi
sudo=""
if [ "$(id -u)" != "0" ]; then
    if command -v sudo >/dev/null 2>&1; then sudo="sudo"; else sudo="none"; fi
fi
if [ "$sudo" = "none" ] || ! command -v apt-get >/dev/null 2>&1; then
    echo "make: gridlib needs the Debian packages: $missing (apt-get install as root);" >&2
    echo "  without them, GRIDLIB_SKIP_MISSING_TOOLS=1 make test skips the tests that use them" >&2
    exit 1
fi
echo "make: installing $missing (apt-get)"
$sudo apt-get update -qq
# shellcheck disable=SC2086  # $missing is a list of package names
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq $missing >/dev/null
