#!/usr/bin/env bash
# commit_subjects.sh BASELINE [MAX] [REPO] - gate of `make check`: the
# subject (first line) of every commit after BASELINE up to HEAD is at most
# MAX characters (default 72), so `git log --oneline` and mail tools show
# it whole. Names each offending commit and exits 1. Skips (exit 0, with
# a message) when REPO (default: the current directory) is no git
# checkout or BASELINE is not in its history (a shallow clone, an export).
set -uo pipefail
base=${1:?usage: commit_subjects.sh BASELINE [MAX] [REPO]}
max=${2:-72}
repo=${3:-.}

if ! command -v git > /dev/null || ! git -C "$repo" rev-parse --git-dir > /dev/null 2>&1; then
    echo "commit subjects: skipped (not a git checkout)"
    exit 0
fi
if ! git -C "$repo" cat-file -e "$base^{commit}" 2> /dev/null ||
   ! git -C "$repo" merge-base --is-ancestor "$base" HEAD 2> /dev/null; then
    echo "commit subjects: skipped (baseline $base is not in this history, e.g. a shallow clone)"
    exit 0
fi

n=0 bad=0
while IFS= read -r line; do
    n=$((n + 1))
    subject=${line#* }
    len=${#subject}
    if [ "$len" -gt "$max" ]; then
        echo "FAIL commit ${line%% *}: subject is $len characters (max $max): ${subject:0:$max}..."
        bad=$((bad + 1))
    fi
done < <(git -C "$repo" log --format='%h %s' "$base..HEAD")

if [ "$bad" -gt 0 ]; then
    echo "commit subjects: $bad of $n commits after $base have a subject over $max characters;" \
         "reword them (git rebase -i $base, 'reword') before merging"
    exit 1
fi
echo "commit subjects: $n commits after $base, every subject <= $max characters"
