#!/usr/bin/env bash
# Rewrites the generated parts of the docs from the built binary (build/candela): docs/settings.md's
# tables from `candela render --help-markdown`. The test docs.settings_table fails until this has run
# after a change to apps/settings_schema.cpp.
set -euo pipefail
cd "$(dirname "$0")/.."
tests/doc_shows_output.sh --update docs/settings.md settings -- build/candela render --help-markdown
