"""The project's UMAA IDL as RTI Connext XML types, the way RTI's own tools describe an IDL file.

RTI's Connector reads types from XML (RTI's "XML type representation"); `rtiddsgen -convertToXml`
would produce it from the IDL, and this does the same for the IDL subset UMAA uses (modules,
structs, enums, typedefs of arrays, sequences, bounded strings, @key and @optional). No
extensibility is written, so RTI applies its own default (appendable), as it does for UMAA's IDL.
"""

from __future__ import annotations

import re
from pathlib import Path

IDL_ROOT = Path(__file__).resolve().parents[4] / "idl"

_BASIC = {
    "double": "float64",
    "float": "float32",
    "long long": "int64",
    "long": "int32",
    "short": "int16",
    "unsigned long": "uint32",
    "unsigned short": "uint16",
    "octet": "uint8",
    "boolean": "boolean",
}
_TOKEN = re.compile(r"//[^\n]*|#[^\n]*|@\w+|::|[A-Za-z_]\w*|\d+|[{};<>,\[\]]")


def _tokens(text: str) -> list[str]:
    return [t for t in _TOKEN.findall(text) if not t.startswith(("//", "#"))]


def _type_xml(tokens: list[str], i: int) -> tuple[str, int]:
    """The XML attributes of a type starting at tokens[i], and the index after it."""
    if tokens[i] == "sequence":
        inner, i = _type_xml(tokens, i + 2)  # skip "sequence <"
        bound = "-1"
        if tokens[i] == ",":
            bound, i = tokens[i + 1], i + 2
        return f'{inner} sequenceMaxLength="{bound}"', i + 1  # skip ">"
    if tokens[i] == "string":
        if tokens[i + 1] == "<":
            return f'type="string" stringMaxLength="{tokens[i + 2]}"', i + 4
        return 'type="string" stringMaxLength="-1"', i + 1
    for words in (3, 2, 1):  # "unsigned long long", "long long", "double"
        name = " ".join(tokens[i : i + words])
        if name in _BASIC:
            return f'type="{_BASIC[name]}"', i + words
    name = tokens[i]
    while tokens[i + 1] == "::":
        name, i = f"{name}::{tokens[i + 2]}", i + 2
    return f'type="nonBasic" nonBasicTypeName="{name}"', i + 1


def _parse(tokens: list[str], extensibility: str | None) -> str:
    """XML for a token stream of module, struct, enum and typedef declarations."""
    out: list[str] = []
    closers: list[str] = []
    ext = f' extensibility="{extensibility}"' if extensibility else ""
    i = 0
    while i < len(tokens):
        t = tokens[i]
        if t == "module":
            out.append(f'<module name="{tokens[i + 1]}">')
            closers.append("</module>")
            i += 3
        elif t == "}":
            i += 1
            closer = closers.pop()
            out.append(closer)
            if i < len(tokens) and tokens[i] == ";":
                i += 1
        elif t == "struct":
            out.append(f'<struct name="{tokens[i + 1]}"{ext}>')
            closers.append("</struct>")
            i += 3
            while tokens[i] != "}":
                flags = []
                while tokens[i].startswith("@"):
                    flags.append({"@key": ' key="true"', "@optional": ' optional="true"'}[tokens[i]])
                    i += 1
                attrs, i = _type_xml(tokens, i)
                out.append(f'<member name="{tokens[i]}" {attrs}{"".join(flags)}/>')
                i += 2  # name ;
            continue
        elif t == "enum":
            out.append(f'<enum name="{tokens[i + 1]}">')
            i += 3
            while tokens[i] != "}":
                if tokens[i] != ",":
                    out.append(f'<enumerator name="{tokens[i]}"/>')
                i += 1
            out.append("</enum>")
            i += 2  # } ;
            continue
        elif t == "typedef":
            attrs, i = _type_xml(tokens, i + 1)
            name = tokens[i]
            dims = ""
            if tokens[i + 1] == "[":
                dims = f' arrayDimensions="{tokens[i + 2]}"'
                i += 3
            out.append(f'<typedef name="{name}" {attrs}{dims}/>')
            i += 2
            continue
        else:
            raise ValueError(f"unexpected IDL token {t!r}")
    return "\n".join(out)


def _files_in_order(root: Path) -> list[Path]:
    """Every IDL file, each after the files it includes (RTI resolves XML types in order)."""
    done: list[Path] = []

    def visit(p: Path) -> None:
        if p in done:
            return
        for inc in re.findall(r'#include "([^"]+)"', p.read_text()):
            visit(root / inc)
        done.append(p)

    for p in sorted((root / "UMAA").rglob("*.idl")):  # one version's tree: idl/ (3.0.1) or idl/umaa-6.0/
        visit(p)
    return done


def types_xml(root: Path = IDL_ROOT, extensibility: str | None = None) -> str:
    """One <types> element with every type of the project's IDL (structs of the given extensibility,
    else RTI's default)."""
    return "<types>\n" + "\n".join(_parse(_tokens(p.read_text()), extensibility) for p in _files_in_order(root)) + "\n</types>"


if __name__ == "__main__":
    print(types_xml())
