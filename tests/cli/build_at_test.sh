#!/usr/bin/env bash
# scripts/build-at.sh, short of a whole build (minutes): each bad input is refused by name before
# anything is built, and a program already built at the asked commit is reused (its path printed,
# nothing configured). Works in a scratch clone of the source, never in the source itself.
# Usage: build_at_test.sh SOURCE_DIR WORK_DIR
set -euo pipefail
source=$1 work=$2
rm -rf "$work" && mkdir -p "$work"
fail() {
  echo "FAILED: $*" >&2
  exit 1
}

if ! git -C "$source" rev-parse --git-dir >/dev/null 2>&1; then
  echo "build-at: $source is not a git checkout: skipped"
  exit 77
fi
# Nothing here may build: a cmake that fails at once stands first on the PATH.
mkdir -p "$work/no-build"
printf '#!/bin/sh\necho "build-at.sh tried to build (cmake $*)" >&2\nexit 3\n' \
  >"$work/no-build/cmake"
chmod +x "$work/no-build/cmake"
export PATH="$work/no-build:$PATH"
clone=$work/clone
git clone --quiet --shared --no-checkout "$source" "$clone"
git -C "$clone" checkout --quiet --detach HEAD
mkdir -p "$clone/scripts"
cp "$source/scripts/build-at.sh" "$clone/scripts/build-at.sh"  # as in the tree under test
git -C "$clone" -c user.name=test -c user.email=test@localhost \
  commit --quiet --allow-empty -m "a second commit"
head=$(git -C "$clone" rev-parse HEAD) before=$(git -C "$clone" rev-parse HEAD~1)
script=$clone/scripts/build-at.sh

# refused: runs SCRIPT ARGS..., expects exit 2 and a message holding PATTERN.
refused() {
  local pattern=$1 out
  shift
  local status=0
  out=$(bash "$@" 2>&1) || status=$?
  [ "$status" -eq 2 ] || fail "'$*' exited with $status, expected 2 (said: $out)"
  grep -q -- "$pattern" <<<"$out" || fail "'$*' said '$out', expected it to name '$pattern'"
}

# fake_program DIR HASH: a program in DIR/build/bin whose --version names HASH's first 12 digits.
fake_program() {
  mkdir -p "$1/build/bin"
  printf '#!/bin/sh\necho "cmbrl 0.0.0 (%s)"\n' "${2:0:12}" >"$1/build/bin/cmbrl"
  chmod +x "$1/build/bin/cmbrl"
}

refused "expected a commit" "$script"
refused "got 3 argument" "$script" a b c
refused "'no-such-commit' is not a commit" "$script" no-such-commit "$work/x"
mkdir -p "$work/bare/scripts" && cp "$script" "$work/bare/scripts/"
refused "is not the top of a git checkout" "$work/bare/scripts/build-at.sh" HEAD  # inside one

# A folder whose source holds another commit is refused, even with a program built there (at
# that other commit), and so is a source with changes to its tracked files.
git -C "$clone" worktree add --quiet --detach "$work/other/source" "$before"
fake_program "$work/other" "$before"
refused "holds something other than ${head:0:12}" "$script" "$head" "$work/other"
rm "$work/other/build/bin/cmbrl"  # (one built at the asked commit would be reused as it is)
echo changed >>"$work/other/source/README.md"
refused "has changes to tracked files" "$script" "$before" "$work/other"

# A program built at the asked commit is reused: its path printed, nothing checked out.
fake_program "$work/built" "$head"
out=$(bash "$script" "$head" "$work/built")
[ "$out" = "$work/built/build/bin/cmbrl" ] || fail "reuse printed '$out'"
[ ! -e "$work/built/source" ] || fail "reuse checked the commit out"
out=$(cd "$work" && bash "$script" "$head" built)  # a folder relative to the caller's
[ "$out" = "$work/built/build/bin/cmbrl" ] || fail "reuse from $work of 'built' printed '$out'"
echo "build-at: bad inputs refused by name, a program built at the commit reused"
