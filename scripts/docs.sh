#!/usr/bin/env bash
# Builds the documentation site from docs/ (mdBook; docs/SUMMARY.md orders the guide, the
# reference and the lab notes) into target/book/index.html, after checking that every
# guide and reference page is in it and no guide page is over 400 lines; then runs the
# guide's commands, scenes and Python blocks and checks the generated reference pages
# against the code. scripts/test.sh runs it with --site (its own tests run the rest).
#
#   scripts/docs.sh [--site]
set -euo pipefail
cd "$(dirname "$0")/.."

MDBOOK_VERSION=0.5.4
mdbook=target/tools/bin/mdbook
if ! { [ -x "$mdbook" ] && "$mdbook" --version | grep -q "v$MDBOOK_VERSION"; }; then
    echo "docs: installing mdBook $MDBOOK_VERSION into target/tools (a few minutes, once)"
    cargo install mdbook --version "$MDBOOK_VERSION" --locked --no-default-features \
        --root target/tools --quiet
fi

failed=0
for page in docs/guide/*.md docs/reference/*.md; do
    if ! grep -q "(${page#docs/})" docs/SUMMARY.md; then
        echo "docs: $page is not in docs/SUMMARY.md" >&2
        failed=1
    fi
done
for page in docs/guide/*.md; do
    lines=$(wc -l < "$page")
    if [ "$lines" -gt 400 ]; then
        echo "docs: $page has $lines lines; a guide page has at most 400" >&2
        failed=1
    fi
done
[ $failed = 0 ] || exit 1

rm -rf target/book
if ! "$mdbook" build docs > target/mdbook.log 2>&1; then
    cat target/mdbook.log >&2
    echo "docs: mdBook failed" >&2
    exit 1
fi
grep -v ' INFO ' target/mdbook.log || true
echo "docs: site in target/book/index.html ($(find target/book -name '*.html' | wc -l) pages)"
[ "${1:-}" = "--site" ] && exit 0

cargo test --release -p tetrasim-cli --test guide_commands --test cli_reference \
    --test parameters --test record_reference
venv=target/pytest-venv
if [ ! -x "$venv/bin/python" ]; then
    echo "docs: the guide's Python blocks need the package's test venv: run scripts/test-python.sh once" >&2
    exit 1
fi
cargo build --release --bin tetrasim
TETRASIM_CLI="$PWD/target/release/tetrasim" "$venv/bin/python" -m pytest -q python/tests/test_guide.py
