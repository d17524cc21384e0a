"""Text a model carries (name, description, source, ...) as data on a terminal and in a page.

:func:`printable` escapes the characters a terminal acts on (C0 and C1 controls, so ESC
sequences, carriage returns and bells; DEL; the bidirectional overrides and isolates
U+202A-U+202E, U+2066-U+2069 and marks; the line and paragraph separators; the lone
surrogates that stand for the undecodable bytes of a file name) as visible
``\\x1b``-style escapes.  :func:`markdown_text` also makes text inert in Markdown and the
HTML it renders to: no tag, no link, no heading, one line.

>>> printable("Duffing\\x1b[2K\\r\\nverdict: stable")
'Duffing\\\\x1b[2K\\\\r\\\\nverdict: stable'
>>> markdown_text("<img src=x onerror=alert(1)> [x](javascript:alert(3))")
'&lt;img src=x onerror=alert\\\\(1\\\\)&gt; \\\\[x\\\\]\\\\(javascript:alert\\\\(3\\\\)\\\\)'
"""

from __future__ import annotations

import re

__all__ = ["printable", "markdown_text", "plot_text"]

_NAMED = {"\n": "\\n", "\r": "\\r", "\t": "\\t"}
#: Characters a terminal or a bidirectional renderer acts on.
_CONTROL = re.compile("[\x00-\x1f\x7f-\x9f\u061c\u200e\u200f\u2028\u2029\u202a-\u202e"
                      "\u2066-\u2069\ud800-\udfff]")
#: What GitHub-flavoured Markdown links on its own: a scheme's colon, ``www.``, an ``@``.
_AUTOLINK = re.compile(r"(?i)(\b(?:https?|ftp)(?=://)|\bwww(?=\.)|(?=@))([:.@])")
_MARKDOWN = re.compile(r"([\\`*_{}\[\]()#+!|~>-])")


def _escape(match: re.Match[str]) -> str:
    char = match.group()
    if char in _NAMED:
        return _NAMED[char]
    code = ord(char)
    return f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}"


def printable(text: str, keep: str = "") -> str:
    """``text`` with every control character (except those in ``keep``) escaped.

    Parameters
    ----------
    text : str
        User text.
    keep : str, optional
        Control characters left as they are (e.g. newline and tab).

    Returns
    -------
    str
        The text, each escaped character as its Python escape sequence.
    """
    if keep:
        return "".join(c if c in keep else _CONTROL.sub(_escape, c) for c in text)
    return _CONTROL.sub(_escape, text)


def markdown_text(text: str) -> str:
    """``text`` as one inert line of Markdown: controls escaped, no HTML, no markup, and
    no link: GitHub-flavoured Markdown links bare ``http://``, ``https://``, ``www.`` and
    e-mail addresses, so their ``:``, ``.`` and ``@`` are backslash-escaped (shown as
    they are, but split from the text the autolinker scans).

    Parameters
    ----------
    text : str
        User text.

    Returns
    -------
    str
        One line of Markdown.
    """
    text = " ".join(printable(text, keep="\n\t").split())
    text = text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    text = _MARKDOWN.sub(r"\\\1", text)
    return _AUTOLINK.sub(r"\1\\\2", text)


def plot_text(text: str, limit: int = 0) -> str:
    """``text`` (a model's name or equation) as one line of a figure: newlines, carriage
    returns, bidirectional overrides and every other control escaped (so no fake line
    and no reordered word is drawn), cut to ``limit`` characters when ``limit`` > 0.
    Draw it with ``parse_math=False``: a ``$`` stays a dollar sign, never mathtext.

    Parameters
    ----------
    text : str
        User text.
    limit : int, optional
        Longest result in characters, "..." included; 0: no limit.

    Returns
    -------
    str
        One line.
    """
    text = printable(text)
    return text if limit <= 0 or len(text) <= limit else text[:limit - 3] + "..."
