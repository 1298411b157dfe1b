# Sphinx configuration of the elastopt documentation site (docs/).
# Build it with scripts/build-docs.sh (Debian: python3-sphinx, python3-myst-parser, doxygen,
# python3-breathe); the script runs Doxygen on include/elastopt/*.h first and passes the XML
# folder in ELASTOPT_DOXYGEN_XML. Pages are MyST Markdown; links to files of the repository
# outside docs/ (bench/results/..., examples/...) become links to those files.
import os
import re

from docutils import nodes

project = "elastopt"
author = "the elastopt authors"
root = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
with open(os.path.join(root, "meson.build"), encoding="utf-8") as f:
    release = version = re.search(r"version\s*:\s*'([^']+)'", f.read()).group(1)

extensions = ["myst_parser"]
source_suffix = {".md": "markdown"}
master_doc = root_doc = "index"
exclude_patterns = ["_build", "images/*.md"]
myst_heading_anchors = 4
myst_enable_extensions = ["dollarmath"]
highlight_language = "none"
html_theme = "alabaster"
html_title = "elastopt " + release
html_static_path = []
# JSON fragments ("time": {...}) and shell transcripts are shown as they are.
suppress_warnings = ["misc.highlighting_failure"]

# The C API page (api.md) needs Breathe and the Doxygen XML of include/elastopt/*.h.
extensions.append("breathe")
breathe_projects = {"elastopt": os.environ.get("ELASTOPT_DOXYGEN_XML", os.path.join(root, "build", "docs-site", "doxygen", "xml"))}
breathe_default_project = "elastopt"
breathe_domain_by_extension = {"h": "c"}
breathe_default_members = ("members", "undoc-members")

# Where links to repository files point: ELASTOPT_SOURCE_URL (e.g. a repository browser's
# base URL) or else the file itself, relative to the built page.
source_url = os.environ.get("ELASTOPT_SOURCE_URL", "").rstrip("/")


def _repo_uri(app, docname, dest, frag):
    relpath = os.path.relpath(dest, root)
    if source_url:
        uri = source_url + "/" + relpath
    else:
        uri = os.path.relpath(dest, os.path.join(app.outdir, os.path.dirname(docname)))
    return uri + ("#" + frag if frag else "")


def _repo_target(app, docname, target):
    """The repository file a relative link target names, if it is not a page of the site."""
    path, _, frag = target.partition("#")
    if not path or re.match(r"^[a-z][a-z0-9+.-]*:", path, re.I):
        return None, None
    here = os.path.dirname(app.env.doc2path(docname))
    dest = os.path.normpath(os.path.join(here, path))
    inside = dest.startswith(app.srcdir + os.sep) and dest.endswith(".md")
    if inside or not dest.startswith(root + os.sep) or not os.path.exists(dest):
        return None, None
    return dest, frag


def _link_repo_files(app, doctree):
    """Links from a page to files of the repository outside docs/ (bench/results/...):
    plain links to the file instead of MyST cross-references, which would not be found."""
    from sphinx import addnodes
    docname = app.env.docname
    for node in list(doctree.findall(addnodes.pending_xref)):
        if node.get("reftype") != "myst":
            continue
        dest, frag = _repo_target(app, docname, node.get("reftarget", ""))
        if dest:
            ref = nodes.reference("", "", internal=False, refuri=_repo_uri(app, docname, dest, frag))
            ref += node.children
            node.replace_self(ref)


def setup(app):
    app.connect("doctree-read", _link_repo_files)
