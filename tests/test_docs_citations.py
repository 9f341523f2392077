"""The code cites the method's derivations in ``docs/method.md`` only, by existing sections.

The derivations once lived in design notes outside the repository, which a clone of it cannot
read. Every citation now has one form, parsed here:

    ``docs/method.md`` section N        or        ``docs/method.md`` sections N, M and P

where each N is the number of a heading of docs/method.md (``## 6. Title`` gives ``6``,
``### 6.3 Title`` gives ``6.3``, ``### 6.2b Title`` gives ``6.2b``). Line breaks (and the
``#`` of a continued comment) may separate the words. A mention of the file without a section
is refused: a page of 700 lines is not a reference.
"""

import re
from pathlib import Path

from support import ROOT

METHOD = ROOT / "docs" / "method.md"
CODE_DIRECTORIES = ("assembly", "solver", "updating", "tests", "bench")

# The retired references, written in pieces so that this file does not contain them itself.
OUTSIDE = ("vtcr-" + "formulation", "formulation" + " notes", "/" + "shared/",
           "interfaces" + ".md")
# "The notes" cited by a section or equation number.
NOTES_BY_NUMBER = re.compile(r"\bnotes'?,?\s+\(?(?:sections?\s+|eq\.\s*)?\d")

SECTION = r"\d+(?:\.\d+)*[a-z]?"
GAP = r"(?:\s|#)+"  # spaces, line breaks and the '#' of a continued comment
CITATION = re.compile(
    rf"docs/method\.md(?:``|`)?,?{GAP}sections?{GAP}"
    rf"(?P<sections>{SECTION}(?:(?:\s*,{GAP}|{GAP}and{GAP}){SECTION})*)")
HEADING = re.compile(rf"^#{{2,6}}\s+(?P<number>{SECTION})\.?\s", re.MULTILINE)


def python_files():
    for directory in CODE_DIRECTORIES:
        yield from sorted((ROOT / directory).rglob("*.py"))


def method_sections():
    """Numbers of the headings of docs/method.md."""
    return HEADING.findall(METHOD.read_text(encoding="utf-8"))


def citations():
    """``(file, line, sections cited)`` for every citation of docs/method.md, and the
    mentions of the file that are not citations in the expected form (this file, whose
    examples test the parser, aside)."""
    found, malformed = [], []
    for path in python_files():
        if path == Path(__file__).resolve():
            continue  # the parser's own examples
        text = path.read_text(encoding="utf-8")
        for mention in re.finditer(r"docs/method\.md", text):
            line = text.count("\n", 0, mention.start()) + 1
            where = f"{path.relative_to(ROOT)}:{line}"
            match = CITATION.match(text, mention.start())
            if match is None:
                malformed.append(where)
            else:
                found.append((where, re.findall(SECTION, match["sections"])))
    return found, malformed


def test_no_citation_of_documents_outside_the_repository():
    """No code file names the retired design notes or the shared interface page."""
    offending = []
    for path in python_files():
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if any(name in line for name in OUTSIDE) or NOTES_BY_NUMBER.search(line):
                offending.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()}")
    assert not offending, "cite ``docs/method.md`` section N instead:\n" + "\n".join(offending)


def test_method_headings_are_numbered_once():
    """Each section number of docs/method.md names one heading."""
    sections = method_sections()
    assert len(sections) > 40
    assert len(set(sections)) == len(sections), sorted(
        s for s in set(sections) if sections.count(s) > 1)


def test_every_cited_section_exists():
    """Every ``docs/method.md`` section N in the code is a heading of docs/method.md, and
    every mention of the file names its section."""
    sections = set(method_sections())
    found, malformed = citations()
    assert not malformed, ("mentions of docs/method.md without ``section N``:\n"
                           + "\n".join(malformed))
    assert len(found) >= 20  # the parser sees the citations the code holds
    missing = [f"{where}: section {number}" for where, numbers in found for number in numbers
               if number not in sections]
    assert not missing, "sections not in docs/method.md:\n" + "\n".join(missing)


def test_citation_parser():
    """The forms the code uses, single and listed sections, across a comment's line break."""
    def parse(text):
        match = CITATION.match(text)
        return None if match is None else re.findall(SECTION, match["sections"])

    assert parse("docs/method.md`` section 6.2b).") == ["6.2b"]
    assert parse("docs/method.md`` section 5.2.") == ["5.2"]
    assert parse("docs/method.md`` sections 1, 2 and 6.2):") == ["1", "2", "6.2"]
    assert parse("docs/method.md`` sections 6.3\n    and 8.9, check I1") == ["6.3", "8.9"]
    assert parse("docs/method.md``\n        # section 9.1; LU") == ["9.1"]
    assert parse("docs/method.md`` for the rest") is None
    assert HEADING.findall("## 6. Joints\n### 6.2b Junction lines\n#### 8.7 J1\n# Title\n") == [
        "6", "6.2b", "8.7"]
