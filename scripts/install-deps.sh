#!/usr/bin/env bash
# Installs the Debian packages the project needs, only those missing, and
# says exactly what it runs. Used by `make deps` (and so by `make` and
# `make test`) and, with --demo, by `make demo`, `make fit` and `make stages`,
# so that a fresh machine needs nothing installed by hand.
set -euo pipefail

# What building the stages and running `make demo` or `make fit` needs
# (`install-deps.sh --demo`: the first command of a fresh machine installs
# only these), then what the tests and benchmarks add.
packages=(
  cmake g++ make pkg-config
  libeigen3-dev            # dense and sparse linear algebra
  libsuitesparse-dev       # CHOLMOD
  libmetis-dev             # METIS, which the static CHOLMOD library calls for its ordering
  libopenblas-dev          # BLAS for CHOLMOD's supernodal factorization (reference BLAS is ~70 % slower)
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev  # CGAL and what its headers need
  libassimp-dev            # mesh formats besides OBJ and PLY
  libembree-dev            # Embree 3: the BVH of the body's closest-point and ray queries
  nlohmann-json3-dev       # JSON specs and reports
  libcli11-dev             # command-line parsing
  catch2                   # unit tests (v2); CMake looks for it whenever it configures the tests
  python3                  # pipelines/fit.mk reads a held pose's opening with it
  libpng-dev libfreetype-dev fonts-dejavu-core  # fit-report: PNG renders and their labels
  librsvg2-bin             # fit-report: the pattern as a picture (rsvg-convert)
  libcairo2-dev            # export-rest: the tiled PDF patterns (A4, Letter, A0, roll)
)
demo_only=false
if [ "${1:-}" = "--demo" ]; then
  demo_only=true
else
  packages+=(
    python3-numpy python3-scipy python3-meshio  # scripts/meshdiff.py
    python3-ezdxf            # reading back the DXF patterns in tests
    python3-matplotlib       # benchmark plots
    poppler-utils            # tests: the PDF pages rasterised (pdftoppm) and read (pdftotext, pdfinfo)
    chromium                 # the fit report's browser test (headless)
    slurm-wlm munge          # the Slurm batch's test runs its own single-node cluster (scripts/tests/local_slurm.py)
  )
fi
# Node.js and npm run the report's tests and install three.js (scripts/web/):
# Debian's packages where the machine has no Node.js of its own.
if ! command -v npm >/dev/null 2>&1; then
  packages+=(nodejs npm)
fi

# `install-deps.sh --fuzz` adds what `make fuzz` needs (clang with libFuzzer).
if [ "${1:-}" = "--fuzz" ]; then
  packages+=(clang libclang-rt-dev)
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "deps: all ${#packages[@]} Debian packages are installed"
else
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  echo "deps: missing: ${missing[*]}"
  echo "deps: running: $sudo apt-get update"
  $sudo apt-get update -qq
  # munge's package starts the system's munged where nothing forbids it (and
  # Slurm's its daemons where /etc/slurm/slurm.conf exists). The project
  # starts none at install, only its own in its test: a policy-rc.d for the
  # duration of the install forbids the start (invoke-rc.d's policy, exit 101).
  policy=/usr/sbin/policy-rc.d
  if [ ! -e "$policy" ]; then
    echo "deps: running: $sudo sh -c 'printf \"#!/bin/sh\\nexit 101\\n\" > $policy' (no service starts during the install)"
    $sudo sh -c "printf '#!/bin/sh\nexit 101\n' > $policy && chmod 755 $policy"
    trap '$sudo rm -f "$policy"' EXIT
  fi
  echo "deps: running: $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends ${missing[*]}"
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# CHOLMOD links the generic libblas.so.3; make sure it resolves to OpenBLAS.
blas=$(readlink -f /usr/lib/x86_64-linux-gnu/libblas.so.3 2>/dev/null || true)
case "$blas" in
  *openblas*) ;;
  *) echo "deps: warning: libblas.so.3 resolves to '${blas:-nothing}', not OpenBLAS; CHOLMOD will be slower" ;;
esac

# npm packages at the exact versions of scripts/web/package-lock.json: three.js
# (copied into every fit report) and the test tools (--demo: three.js only,
# `npm ci --omit=dev`). Reinstalled when the lock file changed since the last
# install, or when the tests need the tools a --demo install left out.
web="$(cd "$(dirname "$0")" && pwd)/web"
npm_flags=(--no-audit --no-fund --loglevel=error)
if $demo_only; then npm_flags+=(--omit=dev); fi
if [ ! -f "$web/node_modules/.package-lock.json" ] || [ "$web/package-lock.json" -nt "$web/node_modules/.package-lock.json" ] ||
   { ! $demo_only && [ ! -d "$web/node_modules/playwright-core" ]; }; then
  echo "deps: running: (cd $web && npm ci ${npm_flags[*]})"
  (cd "$web" && npm ci "${npm_flags[@]}")
else
  echo "deps: npm packages of scripts/web are installed"
fi
