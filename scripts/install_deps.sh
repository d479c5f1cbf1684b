#!/usr/bin/env bash
# Install what mpm-geo needs to build, run and test, and nothing that is already there.
#
#   scripts/install_deps.sh                  compilers, libraries, Python venv
#   scripts/install_deps.sh --with-paraview  also ParaView's pvbatch (used by the tests)
#   scripts/install_deps.sh --with-coarray   also OpenCoarrays and Open MPI (make coarray)
#   scripts/install_deps.sh --with-fuzz      also AFL++ and GCC's plugin headers (make fuzz)
#
# System packages come from apt (Debian/Ubuntu); only missing ones are installed, through sudo
# when not root. Python packages go into .venv/ from postproc/requirements.txt and are only
# reinstalled when that file changes (hash kept in .venv/.requirements.stamp).
# Set MPM_SKIP_SYSTEM_DEPS=1 to skip the apt step (other distributions, or no admin rights).
set -euo pipefail

usage() {
    sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'
}

with_paraview=0
with_coarray=0
with_fuzz=0
for arg in "$@"; do
    case "$arg" in
        --with-paraview) with_paraview=1 ;;
        --with-coarray) with_coarray=1 ;;
        --with-fuzz) with_fuzz=1 ;;
        -h | --help) usage; exit 0 ;;
        *) echo "install_deps.sh: unknown option '$arg' (try --help)" >&2; exit 2 ;;
    esac
done

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"

packages=(gfortran cmake make pkg-config libhdf5-dev libcjson-dev python3 python3-venv)
if [ "$with_paraview" = 1 ]; then
    # pvbatch is in 'paraview'; its Python modules (paraview.simple) are only recommended, and
    # so is the MPI launcher that pvbatch's MPI_Init needs (orted, from mpi-default-bin).
    packages+=(paraview python3-paraview mpi-default-bin)
fi
if [ "$with_coarray" = 1 ]; then
    # caf, cafrun and libcaf_openmpi over Open MPI (the coarray build, tests/parallel)
    packages+=(libcoarrays-openmpi-dev libopenmpi-dev openmpi-bin)
fi
if [ "$with_fuzz" = 1 ]; then
    # afl-fuzz, afl-tmin and the AFL++ runtime; the coverage plugin (tests/fuzz/afl_gcc_cov.cc)
    # is compiled with g++ against the plugin headers of the gfortran in use
    gcc_major=$(gfortran -dumpversion 2> /dev/null | cut -d. -f1 || true)
    if [ -z "$gcc_major" ] && command -v apt-cache > /dev/null 2>&1; then
        gcc_major=$(apt-cache depends gfortran 2> /dev/null |
            awk '$1 == "Depends:" && $2 ~ /^gfortran-[0-9]+$/ { sub("gfortran-", "", $2); print $2 }')
    fi
    packages+=(afl++ g++ "gcc-${gcc_major:-12}-plugin-dev")
fi

# ---------------------------------------------------------------------------------------------
# System packages
# ---------------------------------------------------------------------------------------------
not_debian() {
    cat >&2 <<EOF
install_deps.sh: apt-get/dpkg not found: this script installs packages on Debian/Ubuntu only.
Install these yourself with your system's package manager:
  - a Fortran compiler: gfortran (GCC >= 10)
  - CMake >= 3.20, make, pkg-config
  - HDF5 with the Fortran bindings, development files (Fedora: hdf5-devel; Arch: hdf5)
  - cJSON development files (Fedora: cjson-devel; Arch: cjson)
  - Python 3 with the venv module
  - optional, for the tests: ParaView with pvbatch and its Python modules
Then run again with MPM_SKIP_SYSTEM_DEPS=1 to set up only the Python environment.
EOF
    exit 1
}

if [ "${MPM_SKIP_SYSTEM_DEPS:-0}" = 1 ]; then
    echo "system packages: skipped (MPM_SKIP_SYSTEM_DEPS=1)"
else
    command -v dpkg-query > /dev/null 2>&1 && command -v apt-get > /dev/null 2>&1 || not_debian

    # One dpkg-query call for all packages; a package only counts when fully installed
    # (not 'deinstall ... config-files' or half-configured).
    installed=$(dpkg-query -W -f='${Package} ${db:Status-Status}\n' "${packages[@]}" \
        2> /dev/null | awk '$2 == "installed" { print $1 }' || true)
    missing=()
    for p in "${packages[@]}"; do
        if ! grep -qx -- "$p" <<< "$installed"; then
            missing+=("$p")
        fi
    done

    if [ "${#missing[@]}" -eq 0 ]; then
        echo "system packages: all present"
    else
        echo "installing: ${missing[*]}"
        sudo_cmd=()
        if [ "$(id -u)" -ne 0 ]; then
            if ! command -v sudo > /dev/null 2>&1; then
                echo "install_deps.sh: not root and sudo is not available; as root, run:" >&2
                echo "  apt-get update && apt-get install --no-install-recommends ${missing[*]}" >&2
                exit 1
            fi
            sudo_cmd=(sudo)
            # No terminal (CI): fail at once instead of waiting for a password.
            [ -t 0 ] || sudo_cmd=(sudo -n)
        fi
        # Wait for another apt/dpkg process to release its lock instead of failing.
        apt_opts=(-o DPkg::Lock::Timeout=600)
        "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get "${apt_opts[@]}" update -qq
        "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get "${apt_opts[@]}" \
            install -y -qq --no-install-recommends "${missing[@]}"
    fi

    # Older distributions ship a CMake that is too old for CMakeLists.txt.
    cmake_version=$(cmake --version | awk 'NR == 1 { print $3 }')
    if [ "$(printf '%s\n' 3.20 "$cmake_version" | sort -V | head -n 1)" != 3.20 ]; then
        echo "install_deps.sh: CMake $cmake_version is too old, mpm-geo needs >= 3.20" \
             "(e.g. 'pip install cmake' or a newer distribution)" >&2
        exit 1
    fi
fi

# ---------------------------------------------------------------------------------------------
# Python environment (.venv) for the post-processing package, pytest and the Fortran linter
# ---------------------------------------------------------------------------------------------
requirements=postproc/requirements.txt
stamp=.venv/.requirements.stamp

# The distribution's interpreter, whose venv module was installed above; else whatever is first.
python=python3
[ -x /usr/bin/python3 ] && python=/usr/bin/python3

if [ ! -x .venv/bin/python ] || ! .venv/bin/python -c '' > /dev/null 2>&1; then
    echo "creating Python environment: .venv ($("$python" --version 2>&1))"
    rm -rf .venv
    if ! "$python" -m venv .venv; then
        echo "install_deps.sh: '$python -m venv' failed: install python3-venv" >&2
        exit 1
    fi
fi

if [ ! -f "$requirements" ]; then
    echo "install_deps.sh: $requirements is missing" >&2
    exit 1
fi
want=$(sha256sum "$requirements" | awk '{ print $1 }')
have=$(cat "$stamp" 2> /dev/null || true)
# The stamp says the file was installed; the entry points say nobody removed the tools since.
if [ "$want" = "$have" ] && [ -x .venv/bin/pytest ] && [ -x .venv/bin/fortitude ]; then
    echo "Python packages: all present (.venv)"
else
    reqs=$(sed -e 's/#.*//' -e 's/[[:space:]]//g' -e '/^$/d' "$requirements" | paste -sd ' ')
    echo "installing Python packages into .venv: $reqs"
    .venv/bin/python -m pip install --disable-pip-version-check -q -r "$requirements"
    echo "$want" > "$stamp"
fi
