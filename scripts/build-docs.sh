#!/usr/bin/env bash
# Build the documentation site from docs/ (Sphinx + MyST Markdown; the C API from the
# headers' /// comments through Doxygen + Breathe). Debian packages: python3-sphinx,
# python3-myst-parser, doxygen, python3-breathe (scripts/setup.sh installs them).
#
#   bash scripts/build-docs.sh [OUTDIR]     # default build/docs-site: OUTDIR/html/index.html
#   bash scripts/build-docs.sh --check      # the docs_site test: build into a temporary
#                                           # folder with -W (warnings are errors, MyST's
#                                           # cross-reference warnings included), then
#                                           # scripts/check-docs.py (relative links and
#                                           # #anchors of every .md, shell blocks bash -n,
#                                           # JSON blocks json.loads); exit 77 without Sphinx
#
# Uses Debian's /usr/bin/python3 (a python3 earlier on PATH may lack Debian's packages).
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
py=/usr/bin/python3
check=0
if [ "${1:-}" = "--check" ]; then check=1; shift; fi
missing=()
$py -c 'import sphinx' 2>/dev/null || missing+=(python3-sphinx)
$py -c 'import myst_parser' 2>/dev/null || missing+=(python3-myst-parser)
$py -c 'import breathe' 2>/dev/null || missing+=(python3-breathe)
command -v doxygen >/dev/null || missing+=(doxygen)
if [ ${#missing[@]} -gt 0 ]; then
  echo "build-docs: missing ${missing[*]} (apt-get install ${missing[*]}, or bash scripts/setup.sh)"
  [ $check = 1 ] && exit 77
  exit 2
fi
if [ $check = 1 ]; then
  out=$(mktemp -d)
  trap 'rm -rf "$out"' EXIT
else
  out=${1:-$src/build/docs-site}
  mkdir -p "$out"
  out=$(cd "$out" && pwd)
fi

# Doxygen: XML of the public headers for Breathe (nothing else is generated).
mkdir -p "$out/doxygen"
cat > "$out/Doxyfile" <<EOF
PROJECT_NAME           = elastopt
INPUT                  = $src/include/elastopt $src/include/elastopt/impl
FILE_PATTERNS          = *.h
OUTPUT_DIRECTORY       = $out/doxygen
GENERATE_XML           = YES
GENERATE_HTML          = NO
GENERATE_LATEX         = NO
OPTIMIZE_OUTPUT_FOR_C  = YES
TYPEDEF_HIDES_STRUCT   = YES
EXTRACT_ALL            = YES
JAVADOC_AUTOBRIEF      = NO
MARKDOWN_SUPPORT       = YES
ENABLE_PREPROCESSING   = YES
MACRO_EXPANSION        = YES
EXPAND_ONLY_PREDEF     = YES
PREDEFINED             = EO_API= __cplusplus_NOT=
QUIET                  = YES
WARNINGS               = NO
WARN_IF_UNDOCUMENTED   = NO
EXCLUDE_SYMBOLS        = EO_X_ENUM
EOF
doxygen "$out/Doxyfile" > "$out/doxygen.log" 2>&1 || { cat "$out/doxygen.log"; exit 1; }

export ELASTOPT_DOXYGEN_XML=$out/doxygen/xml
opts=(-q -b html -d "$out/doctrees" -c "$src/docs")
[ $check = 1 ] && opts+=(-W --keep-going)
if ! $py -m sphinx "${opts[@]}" "$src/docs" "$out/html" 2> "$out/sphinx.log"; then
  cat "$out/sphinx.log"
  echo "docs_site: the site does not build without warnings"
  exit 1
fi
[ -s "$out/sphinx.log" ] && cat "$out/sphinx.log"
if [ $check = 1 ]; then
  $py "$src/scripts/check-docs.py" "$src"
  n=$(find "$out/html" -name '*.html' | wc -l)
  echo "docs_site: $n HTML pages built with -W"
else
  echo "build-docs: $out/html/index.html"
fi
