"""csrc.py - C sources read as text for the gates of tools/check/ (no
compiler): the function definitions with the words before their name and
the names they call, and the quoted includes. The house style is assumed:
a definition starts at the line's first column."""
import re

KEYWORDS = {'if', 'for', 'while', 'switch', 'return', 'sizeof', 'do', 'else'}
DEFINITION = re.compile(r'^(?P<head>[A-Za-z_][\w \t\*]*?)\b(?P<name>[A-Za-z_]\w*)\s*'
                        r'\((?P<params>(?:[^;{}()]|\([^;{}()]*\))*)\)\s*\{', re.MULTILINE)
CALL = re.compile(r'\b([A-Za-z_]\w*)\s*\(')
INCLUDE = re.compile(r'(?m)^[ \t]*#[ \t]*include[ \t]*"([^"]+)"')


def read(path):
    with open(path) as f:
        return f.read()


def strip_comments(text):
    """Comments, strings and preprocessor lines blanked, newlines kept."""
    def blank(m):
        return re.sub(r'[^\n]', ' ', m.group(0))
    text = re.sub(r'/\*.*?\*/|//[^\n]*|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'', blank, text, flags=re.DOTALL)
    return re.sub(r'(?m)^[ \t]*#.*(?:\\\n.*)*$', blank, text)


def body_end(text, open_at):
    depth = 0
    for i in range(open_at, len(text)):
        if text[i] == '{':
            depth += 1
        elif text[i] == '}':
            depth -= 1
            if depth == 0:
                return i
    return len(text)


def definitions(text):
    """[(match, head words)] of the function definitions in text (comments stripped)."""
    out = []
    for m in DEFINITION.finditer(text):
        head = m.group('head').split()
        if m.group('name') in KEYWORDS or not head or head[0] in KEYWORDS or 'typedef' in head:
            continue
        out.append((m, head))
    return out


def functions(path):
    """{name: (head words, names called)} of the definitions in path."""
    text = strip_comments(read(path))
    out = {}
    for m, head in definitions(text):
        end = body_end(text, m.end() - 1)
        out[m.group('name')] = (head, set(CALL.findall(text[m.end():end])) - KEYWORDS)
    return out


def includes(path):
    """The names of path's quoted includes, as written."""
    return INCLUDE.findall(read(path))
