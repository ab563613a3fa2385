#!/usr/bin/env bash
# `make install`: puts joshuac and the runtime's console scripts on PATH for new shells.
#
# Each command gets a small wrapper in BINDIR (default ~/.local/bin) that runs this checkout's
# .venv/bin/<command> by its absolute path, so a rebuilt environment (`make setup`) is picked up as
# it is, and a missing one is reported with the command that restores it. When a login shell's PATH
# lacks BINDIR, one marked line adding it goes to the shell start-up files bash reads (the login file
# and ~/.bashrc); nothing else in them is touched. `make uninstall` removes both again.
set -euo pipefail
cd "$(dirname "$0")/.."
REPO="$PWD"
BINDIR="${BINDIR:-$HOME/.local/bin}"
MARK="# joshuac make install"

commands() {
  # The console scripts of this checkout's packages, as installed in .venv (their pyproject files list them).
  "$REPO/.venv/bin/python" -c 'from importlib.metadata import entry_points
print(*sorted(e.name for e in entry_points(group="console_scripts") if e.dist.name in ("joshuac", "joshua-runtime")))'
}

login_file() {
  # The file a bash login shell reads: the first of these that exists, else ~/.profile.
  for name in .bash_profile .bash_login .profile; do
    if [ -e "$HOME/$name" ]; then echo "$HOME/$name"; return; fi
  done
  echo "$HOME/.profile"
}

path_line() {
  printf 'case ":$PATH:" in *:%s:*) ;; *) PATH=%s:"$PATH"; export PATH ;; esac  %s\n' \
    "$(printf %q "$BINDIR")" "$(printf %q "$BINDIR")" "$MARK"
}

uninstall() {
  # Every wrapper make install wrote carries the mark on its second line, whatever command it runs.
  for wrapper in "$BINDIR"/joshua*; do
    if [ -f "$wrapper" ] && sed -n 2p "$wrapper" | grep -qF "$MARK"; then
      rm -f "$wrapper" && echo "install: removed $wrapper"
    fi
  done
  for file in "$(login_file)" "$HOME/.bashrc"; do
    if [ -f "$file" ] && grep -qF "$MARK" "$file"; then
      grep -vF "$MARK" "$file" > "$file.joshuac-tmp" || true
      cat "$file.joshuac-tmp" > "$file" && rm -f "$file.joshuac-tmp"
      echo "install: removed the PATH line from $file"
    fi
  done
}

install() {
  local names
  names="$(commands)"
  read -r -a COMMANDS <<< "$names"
  mkdir -p "$BINDIR"
  for command in "${COMMANDS[@]}"; do
    target="$BINDIR/$command"
    if [ -e "$target" ] && ! grep -qF "$MARK" "$target" 2>/dev/null; then
      echo "install: $target exists and was not written by make install; left as it is" >&2
      exit 1
    fi
    program="$REPO/.venv/bin/$command"
    {
      echo '#!/bin/bash'
      echo "$MARK: runs $command of the checkout $REPO (run make install again after moving it)."
      echo "program=$(printf %q "$program")"
      echo 'if [ ! -x "$program" ]; then'
      echo "  echo \"$command: \$program is missing; run: make -C $(printf %q "$REPO") setup\" >&2"
      echo '  exit 127'
      echo 'fi'
      echo 'exec "$program" "$@"'
    } > "$target.joshuac-tmp"
    chmod 755 "$target.joshuac-tmp"
    mv -f "$target.joshuac-tmp" "$target"
  done
  echo "install: ${COMMANDS[*]} -> $BINDIR"
  login_path="$(env -i HOME="$HOME" USER="${USER:-}" bash -lc 'printf %s "$PATH"' 2>/dev/null || true)"
  case ":$login_path:" in
    *":$BINDIR:"*) return ;;
  esac
  for file in "$(login_file)" "$HOME/.bashrc"; do
    if ! grep -qF "$MARK" "$file" 2>/dev/null; then
      path_line >> "$file"
      echo "install: added $BINDIR to PATH in $file (new shells have it; this one: export PATH=\"$BINDIR:\$PATH\")"
    fi
  done
}

case "${1:-install}" in
  install) install ;;
  uninstall) uninstall ;;
  *) echo "usage: $0 [install|uninstall]" >&2; exit 2 ;;
esac
