#!/usr/bin/env bash
# Builds the cmbrl program as it was at a commit (the build an experiment names for its runs) and
# prints the program's path as the last line of its output:
#
#   bash scripts/build-at.sh e91ffa7 [DIR]
#   cmbrl sweep experiments/paper-size --jobs 1 \
#       --train-with "$(bash scripts/build-at.sh e91ffa7 | tail -n 1)"
#
# The commit is checked out as a detached git worktree in DIR/source (default DIR:
# build/at/<the commit's first 12 hex digits>) and built (Release, the program alone) into
# DIR/build; the working tree of this checkout is not touched. A second call with a program
# already built at that commit prints its path and builds nothing. Needs the Debian packages of
# scripts/install-deps.sh, as a build of today's tree does.
set -euo pipefail
caller=$(pwd)  # a DIR given relative is relative to where the script was called from
cd "$(dirname "$0")/.."

fail() {
  echo "scripts/build-at.sh: $*" >&2
  exit 2
}

if [ "$#" -lt 1 ] || [ "$#" -gt 2 ]; then
  fail "expected a commit and at most one folder (build-at.sh COMMIT [DIR]), got $# argument(s)"
fi
# The checkout the script belongs to, not one it happens to sit inside.
top=$(git rev-parse --show-toplevel 2>/dev/null || true)
[ "$top" = "$(pwd -P)" ] ||
  fail "$(pwd) is not the top of a git checkout: a commit can be built only from its repository"
commit=$(git rev-parse --verify --quiet "$1^{commit}") ||
  fail "'$1' is not a commit of this repository: expected a hash or tag that \`git log\`" \
    "shows (a shallow clone may lack old commits: \`git fetch --unshallow\`)"
short=${commit:0:12}
dir=${2:-build/at/$short}
[ "$#" -lt 2 ] || [[ "$dir" = /* ]] || dir=$caller/$dir
mkdir -p "$dir"
dir=$(cd "$dir" && pwd)
source_dir=$dir/source build_dir=$dir/build program=$dir/build/bin/cmbrl

# Whether the program is built at this commit: its --version names it, without "-dirty".
built_at_commit() { [ -x "$program" ] && "$program" --version 2>/dev/null | grep -q "($short)"; }

if built_at_commit; then
  echo "$program"
  exit 0
fi

if [ -e "$source_dir" ]; then
  # Left by an earlier call: it must hold this commit, untouched.
  [ "$(git -C "$source_dir" rev-parse HEAD 2>/dev/null)" = "$commit" ] ||
    fail "$source_dir holds something other than $short: remove it" \
      "(git worktree remove --force $source_dir) or give another DIR"
  [ -z "$(git -C "$source_dir" status --porcelain --untracked-files=no)" ] ||
    fail "$source_dir has changes to tracked files: a build there would not be $short's"
else
  git worktree prune
  git worktree add --detach "$source_dir" "$commit" >&2
fi

# With ccache, absolute paths below the checkout are rewritten relative to the build folder,
# so a build of the same commit in another checkout of this repository reuses these objects.
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$(pwd)}
generator=()
if command -v ninja >/dev/null 2>&1; then generator=(-G Ninja); fi
if [ ! -f "$build_dir/CMakeCache.txt" ]; then
  cmake -S "$source_dir" -B "$build_dir" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release >&2
fi
cmake --build "$build_dir" --target cmbrl_app --parallel "$(nproc)" >&2
built_at_commit || fail "$program does not say it is $short's build: $("$program" --version)"
echo "$program"
