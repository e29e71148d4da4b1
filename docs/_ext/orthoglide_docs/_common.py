"""What the generators share: the package's name, the log, reST helpers."""

from __future__ import annotations

from docutils import nodes
from docutils.parsers.rst import states as rst_states
from docutils.parsers.rst.states import RSTStateMachine
from docutils.statemachine import StringList
from sphinx.util import logging
from sphinx.util.docutils import SphinxDirective

PACKAGE = "orthoglide_pin"

logger = logging.getLogger("orthoglide_docs")


def title(text: str, char: str) -> list[str]:
    """A reST section title."""
    return [text, char * len(text), ""]


def parse_rst(directive: SphinxDirective, lines: list[str], source: str) -> list[nodes.Node]:
    """Parse reST into the page's document, whatever the page's own markup.

    The text is parsed into the document itself (so that its labels and
    options are the page's), then handed back to stand where the directive is.
    """
    document = directive.state.document
    before = len(document.children)
    machine = RSTStateMachine(state_classes=rst_states.state_classes, initial_state="Body")
    machine.run(StringList(lines, source), document)
    machine.unlink()
    new = list(document.children[before:])
    del document.children[before:]
    return new
