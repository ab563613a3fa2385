#!/usr/bin/env bash
# Prepares a machine for `make run` / `make test`: apt packages, uv, and the locked environment.
set -euo pipefail
cd "$(dirname "$0")/.."
export UV_PYTHON_DOWNLOADS=never

# System packages: systemd-analyze (unit checks), Mesa EGL (MuJoCo offscreen rendering), the libraries
# Qt needs offscreen, the compiler and JSON header of the C++ nodes (g++ also builds the ROS
# interface packages no wheel ships, from interfaces/), Node.js with npm (the dashboard page) and
# Chromium's headless shell (the browser tests drive it through Playwright), what builds and runs
# container images without a daemon: podman with runc and catatonit, debootstrap for a registry-free base,
# and OpenSSH's server and client (the fleet tests run one sshd per simulated robot, in network namespaces;
# never on this machine's network).
APT_PACKAGES=(systemd libegl1 libegl-mesa0 libgl1-mesa-dri libgles2 libgl1 libxkbcommon0 libfontconfig1 libfreetype6 libdbus-1-3 libglib2.0-0 fonts-dejavu-core g++ make nlohmann-json3-dev nodejs chromium-headless-shell podman runc catatonit debootstrap openssh-server openssh-client)
missing=()
for package in "${APT_PACKAGES[@]}"; do
  dpkg -s "$package" >/dev/null 2>&1 || missing+=("$package")
done
if [ ${#missing[@]} -gt 0 ]; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    echo "setup: installing ${missing[*]}"
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  else
    echo "setup: warning: missing system packages (install them as root): ${missing[*]}" >&2
  fi
fi

if ! command -v uv >/dev/null 2>&1; then
  echo "setup: installing uv"
  python3 -m pip install --quiet --user uv 2>/dev/null || python3 -m pip install --quiet uv
  export PATH="$HOME/.local/bin:$PATH"
fi
# --inexact: the ROS 2 wheels ship setuptools egg-info folders that uv takes for extraneous
# distributions; removing them would delete rclpy and the message packages themselves.
# Bytecode is compiled up front: with PYTHONDONTWRITEBYTECODE set, every node process would
# otherwise compile rclpy, torch and the project from source at each start. uv walks the whole
# environment to do it (1.7 s with nothing to compile), so only after a sync that installed or removed a
# distribution: that changes site-packages or one of its entries.
uv sync --locked --inexact --quiet
compiled=.venv/.bytecode-compiled
if [ ! -f "$compiled" ] || [ -n "$(find .venv/lib/python*/site-packages -maxdepth 1 -newer "$compiled" -print -quit)" ]; then
  uv sync --locked --inexact --quiet --compile-bytecode
  touch "$compiled"
fi
.venv/bin/python scripts/build_ros_interfaces.py  # tf2_msgs; a no-op when its stamp is current
.venv/bin/python -m compileall -q joshua_codegen core/joshua_core runtime/joshua_runtime bench testsupport >/dev/null
# A build fills the compiled-template cache, unless it is newer than every template (an entry whose template
# is unchanged is kept as it is, so the directory is touched after the build).
template_cache=joshua_codegen/_template_cache
if [ ! -d "$template_cache" ] || [ -n "$(find templates -name '*.j2' -newer "$template_cache" -print -quit)" ]; then
  warm=$(mktemp -d)
  .venv/bin/joshuac build config/robots/so100_leader_follower.pbtxt -o "$warm/out" >/dev/null 2>&1 || true
  rm -rf "$warm"
  touch "$template_cache"
fi

# C++ node binaries (build/bin/), compiled against the ROS 2 wheels just installed; a no-op when up to date.
if ! make --no-print-directory -s -C cpp; then
  echo "setup: warning: the C++ nodes did not build; nodes preferring CPP fall back to Python" >&2
fi

# The dashboard's page: its types rendered from the API's schema (a no-op when they are up to date), then
# installed from web/package-lock.json and built into web/dist, only when a source, the schema, the lock
# file or the build configuration is newer than the last build.
.venv/bin/python -m joshua_runtime.dashboard.api_typescript --if-changed
if command -v npm >/dev/null 2>&1; then
  stamp=web/dist/.built
  if [ ! -f "$stamp" ] || [ -n "$(find web/src runtime/joshua_runtime/dashboard/api.schema.json web/index.html web/fleet.html web/package-lock.json web/vite.config.ts web/tsconfig.json web/tailwind.config.js -newer "$stamp" -print -quit)" ]; then
    echo "setup: building the dashboard page (web/dist)"
    (cd web && npm ci --no-audit --no-fund --loglevel=error && npx --no-install tsc --noEmit -p . && npx --no-install vite build --logLevel error)
    touch "$stamp"
  fi
else
  echo "setup: warning: npm is missing; the dashboard page (web/dist) is not built" >&2
fi
