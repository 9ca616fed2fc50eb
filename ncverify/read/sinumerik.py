"""Reader for SINUMERIK 840D programs: one line to one block of statements.

A block is ``[/] [N..] [LABEL:] item item ...``: address words (``G1``, ``X10``,
``X=AC(R1+2)``, ``CR=5``, ``T="DRILL"``), assignments (``R1=5``, ``ZAEHL=ZAEHL+1``,
``$TC_DP6[1,1]=5``), keyword statements (``IF``/``ELSE``/``ENDIF``, ``WHILE``, ``FOR``,
``REPEAT``/``UNTIL``, ``LOOP``, ``CASE``, ``GOTOF``, ``DEF``, ``PROC``, ``MCALL``, frames) and
calls by name with an argument list (``CYCLE81(10,0,2,-5)``, ``MYSUB``).

The manual's OCR text writes full-width ``；（），：``, curly quotes and en dashes; they are
read as their ASCII twins (:func:`normalize`), so the manual's examples read as written.
The reader never raises: text it cannot read gives a :class:`~ncverify.read.iso.SyntaxProblem`.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field

from .. import ir
from .iso import SyntaxProblem
from .limits import MAX_NESTING, MAX_TERMS, nesting_message, terms_message

_TWINS = str.maketrans({"；": ";", "（": "(", "）": ")", "，": ",", "、": ",", "：": ":", "“": '"', "”": '"', "„": '"',
                        "‟": '"', "–": "-", "—": "-", "＝": "=", "　": " ", "\t": " "})


def normalize(text: str) -> str:
    """The line with the manual's typographic characters replaced by ASCII (same length)."""
    return text.translate(_TWINS)


_OFFSET_VARIABLES = ("$AA_OFF", "$AA_ETRANS", "$P_", "$TC_", "TOFF")  # what a synchronised action may write that moves the tool or the part


@dataclass(slots=True)
class Item:
    """One thing a block says. ``kind``: ``word`` (address ``name`` = ``value``, ``mode``
    AC/IC), ``assign``, ``call`` (``name``, ``args`` list of Expr or None for omitted,
    ``arg_spans``), ``mcall``, ``def``, ``proc``, ``if``, ``else``, ``endif``, ``while``,
    ``endwhile``, ``for``, ``endfor``, ``repeat``, ``until``, ``loop``, ``endloop``, ``goto``
    (``name`` = direction, ``value`` = label, ``condition``), ``case``, ``frame``, ``ret``,
    ``setal``, ``msg``, ``repeat_section``, ``unsupported`` (``name`` says what; ``value`` True where it
    may write an offset, a frame or tool data)."""

    kind: str
    start: int
    end: int
    name: str = ""
    value: object = None
    mode: str | None = None
    args: list = field(default_factory=list)
    arg_spans: list = field(default_factory=list)
    condition: object = None
    extra: object = None


@dataclass(slots=True)
class ReadBlock:
    line: int
    start: int
    end: int
    items: list[Item] = field(default_factory=list)
    skip: bool = False
    number: int | None = None
    label: str | None = None
    comments: list[tuple[str, int, int]] = field(default_factory=list)
    problem: SyntaxProblem | None = None
    header: tuple[str, str] | None = None  # %_N_NAME_MPF -> ("NAME", "MPF")


class _Fail(Exception):
    def __init__(self, message: str, position: int):
        super().__init__(message)
        self.position = position


_TOKEN = re.compile(r"""
    (?P<space>\s+)
  | (?P<number>(?:\d+\.?\d*|\.\d+)(?:EX[+-]?\d+)?)
  | (?P<string>"[^"]*"|'[^']*')
  | (?P<name>[A-Za-z_$][A-Za-z0-9_$]*(?:(?<=[0-9])\.[0-9]*)?)
  | (?P<op><<|==|<>|<=|>=|[-+*/=<>()\[\],:])
""", re.VERBOSE)

# Addresses that take a number written straight after them (X10, G1, M30, N10).
_ADDRESS = re.compile(r"(CHF|CHR|RND|RNDM|CR|AP|RP|ANG|[A-Z])([+-]?(?:\d+\.?\d*|\.\d+))", re.IGNORECASE)
# Addresses written ADDRESS=value (axis, feed, speed, tool, arc words).
EQUALS_ADDRESSES = frozenset({
    "X", "Y", "Z", "A", "B", "C", "U", "V", "W", "I", "J", "K", "F", "S", "T", "D", "H", "E", "L", "P", "Q",
    "CR", "AP", "RP", "CHF", "CHR", "RND", "RNDM", "ANG", "SPOS", "SPOSA", "AR", "ADIS", "ADISPOS", "TURN",
    "I1", "J1", "K1", "FA", "G", "M", "LIMS", "X1", "Y1", "Z1", "X2", "Z2", "SF", "OVR", "DC", "ACP", "ACN", "CIP",
    "RPL",  # ROT RPL=30: rotation in the active plane
})
_BLOCK_KEYWORDS = frozenset({
    "IF", "ELSE", "ENDIF", "WHILE", "ENDWHILE", "FOR", "ENDFOR", "REPEAT", "REPEATB", "UNTIL", "LOOP", "ENDLOOP",
    "CASE", "GOTOF", "GOTOB", "GOTO", "GOTOC", "DEF", "PROC", "MCALL", "RET", "TRANS", "ATRANS", "ROT", "AROT",
    "ROTS", "AROTS", "MIRROR", "AMIRROR", "SCALE", "ASCALE", "WHEN", "WHENEVER", "EVERY", "ID", "IDS", "EXTCALL",
    "ISOCALL", "CALL", "PCALL", "SAVE", "DISPLOF", "DISPLON", "STOPRE", "SETAL", "MSG", "WORKPIECE", "CTABDEF",
    "CTABEND", "REDEF", "SPOS", "SPOSA", "M", "G", "T", "D", "H", "S", "F", "CANCEL", "DO", "ENDPROC", "EXTERN",
})
_INDIRECT_CODES = ("M", "G", "T", "D", "H", "S", "F")
_OLD_SUBPROGRAM = re.compile(r"L\d+")
FRAME_KEYWORDS = frozenset({"TRANS", "ATRANS", "ROT", "AROT", "ROTS", "AROTS", "MIRROR", "AMIRROR", "SCALE", "ASCALE"})
DEF_TYPES = frozenset({"REAL", "INT", "BOOL", "CHAR", "STRING", "AXIS", "FRAME"})
_COMPARE = {"==": "EQ", "<>": "NE", "<": "LT", ">": "GT", "<=": "LE", ">=": "GE"}
_HEADER = re.compile(r"^\s*%_N_(\w+?)_(MPF|SPF|DEF|COM|CYP)\b", re.IGNORECASE)
_LABEL = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)\s*:(?!=)")
_NUMBER_WORD = re.compile(r"[Nn](\d+)(?![\w.])")
_NUMBER_AGAINST_NAME = re.compile(r"[Nn](\d+)(?=([A-Za-z_][A-Za-z0-9_]*))")
_SKIP = re.compile(r"/\d?")
# Functions the interpreter evaluates, under their SINUMERIK names.
FUNCTIONS = {"SIN": "SIN", "COS": "COS", "TAN": "TAN", "ASIN": "ASIN", "ACOS": "ACOS", "SQRT": "SQRT", "ABS": "ABS",
             "ROUND": "ROUND", "TRUNC": "FIX", "LN": "LN", "EXP": "EXP", "ATAN": "ATAN"}
# MINVAL/MAXVAL: the smaller / larger of two values (840D programming knowledge)
TWO_ARGUMENT_FUNCTIONS = {"MINVAL": "MIN", "MAXVAL": "MAX"}
# Predefined functions that may be written with a blank before their parenthesis (SIN (30));
# any other name needs its '(' straight after it to be a call.
PREDEFINED_FUNCTIONS = frozenset(FUNCTIONS) | {"POT", "AC", "IC", "ATAN2", "MINVAL", "MAXVAL", "BOUND", "CTRANS", "CROT",
                                              "STRLEN", "INDEX", "RINDEX", "MINDEX", "MATCH", "SUBSTR", "TOUPPER",
                                              "TOLOWER", "NUMBER", "ISNUMBER", "ISVAR", "AXNAME", "AXSTRING", "SPI"}


def read_line(text: str, line: int) -> ReadBlock:
    """Read one line (already decoded) into a block; never raises."""
    text = normalize(text)
    stripped = text.rstrip()
    first = len(text) - len(text.lstrip())
    block = ReadBlock(line, first, len(stripped))
    header = _HEADER.match(text)
    if header:
        block.header = (header.group(1).upper(), header.group(2).upper())
        return block
    code, comment_at = _split_comment(text)
    if comment_at is not None:
        block.comments.append((text[comment_at + 1:].strip(), comment_at, len(stripped)))
    try:
        _BlockParser(code, block).parse()
    except _Fail as failure:
        end = min(len(code.rstrip()), failure.position + 1) if failure.position < len(code.rstrip()) else failure.position
        block.problem = SyntaxProblem(str(failure), failure.position, max(end, failure.position + 1))
    return block


def _split_comment(text: str) -> tuple[str, int | None]:
    """Code and the column of the ';' that starts the comment (outside strings)."""
    quote = None
    for index, char in enumerate(text):
        if quote:
            if char == quote:
                quote = None
        elif char == '"':
            quote = char
        elif char == ";":
            return text[:index], index
    return text, None


_AFTER_AN_OPERAND = frozenset({",", ")", ""})  # texts of the tokens no operator starts with (the end of the block: "")


class _BlockParser:
    def __init__(self, code: str, block: ReadBlock):
        self.code = code
        self.block = block
        self.tokens = self._tokenize(code)
        self.index = 0
        self.depth = 0  # expressions open inside one another (limits.MAX_NESTING)
        self.terms = 0  # operands read in this block (limits.MAX_TERMS)

    # ------------------------------------------------------------------ tokens

    @staticmethod
    def _tokenize(code: str) -> list[tuple[str, str, int, int]]:
        tokens = []
        position = 0
        while position < len(code):
            match = _TOKEN.match(code, position)
            if match is None:
                raise _Fail(f"unexpected character '{code[position]}'", position)
            kind = match.lastgroup
            if kind != "space":
                text = match.group()
                if kind == "string" and len(text) < 2:
                    raise _Fail("string without its closing quote", position)
                tokens.append((kind, text, match.start(), match.end()))
            position = match.end()
        for kind, text, start, _end in tokens:
            if kind == "string" and (text.count('"') == 1 or (text[0] == "'" and text.count("'") == 1)):
                raise _Fail("string without its closing quote", start)
        return tokens

    def peek(self, offset: int = 0):
        index = self.index + offset
        return self.tokens[index] if index < len(self.tokens) else ("end", "", len(self.code.rstrip()), len(self.code.rstrip()))

    def take(self):
        token = self.peek()
        self.index += 1
        return token

    def at(self, text: str) -> bool:
        token = self.peek()
        return token[0] in ("op", "name") and token[1].upper() == text

    def expect(self, text: str):
        token = self.peek()
        if not self.at(text):
            raise _Fail(f"'{text}' expected, found '{token[1] or 'end of block'}'", token[2])
        return self.take()

    def done(self) -> bool:
        return self.index >= len(self.tokens)

    # ------------------------------------------------------------------ block

    def parse(self) -> None:
        block = self.block
        self._prefix()
        while not self.done():
            self._item()
        if block.items:
            block.start = min(block.start, block.items[0].start)

    def _prefix(self) -> None:
        """Block skip, block number and label."""
        code, block = self.code, self.block
        position = len(code) - len(code.lstrip())
        skip = _SKIP.match(code, position)
        if skip:
            block.skip = True
            position = skip.end()
        while position < len(code) and code[position] == " ":
            position += 1
        number = _NUMBER_WORD.match(code, position) or self._number_against_keyword(position)
        if number:
            block.number = int(number.group(1))
            position = number.end()
            while position < len(code) and code[position] == " ":
                position += 1
        label = _LABEL.match(code, position)
        if label and label.group(1).upper() not in _BLOCK_KEYWORDS | DEF_TYPES:
            block.label = label.group(1).upper()
            position = label.end()
        while self.index < len(self.tokens) and self.tokens[self.index][2] < position:
            self.index += 1

    def _number_against_keyword(self, position: int):
        """``N10DEF INT I``, ``N20GOTOF END``: the block number written against a keyword.
        The name token the two make is cut at the keyword, which is then read as usual."""
        match = _NUMBER_AGAINST_NAME.match(self.code, position)
        if match is None or match.group(2).upper() not in _BLOCK_KEYWORDS | DEF_TYPES:
            return None
        for index, (kind, text, start, end) in enumerate(self.tokens):
            if start < match.end() < end:
                self.tokens[index] = (kind, self.code[match.end():end], match.end(), end)
        return match

    def _item(self) -> None:
        kind, text, start, end = self.peek()
        upper = text.upper()
        if kind != "name":
            if kind == "op" and text == ":":
                raise _Fail("a label must start the block (after the block number)", start)
            raise _Fail(f"unexpected '{text}'", start)
        handler = getattr(self, f"_kw_{upper.lower()}", None) if upper in _BLOCK_KEYWORDS else None
        following = self.peek(1)
        if handler is not None and not (following[1] == "=" and upper in EQUALS_ADDRESSES | {"SPOS", "SPOSA"} - {"M", "G", "T", "D", "H"}):
            if upper in _INDIRECT_CODES and following[1] not in ("=", "["):
                handler = None
            if handler is not None:
                self.take()
                handler(start)
                return
        if _OLD_SUBPROGRAM.fullmatch(upper):  # L140, L140(2): a subprogram named by number
            self.take()
            if self.at("("):
                self._call(upper, start)
            else:
                self.block.items.append(Item("call", start, end, upper))
            return
        address = _ADDRESS.match(self.code, start)
        if address and address.group(1).upper() in EQUALS_ADDRESSES | {"N", "R", "O"} and (address.end() <= end or address.start(2) == end):
            self._address_run(start, end)
            return
        self.take()
        if following[1] == "=":
            self.take()
            self._equals(upper, start)
        elif following[1] == "[":
            self._indexed(upper, start)
        elif following[1] == "(" and following[2] >= end:
            self._call(upper, start)
        else:
            self._bare_name(upper, start, end)

    def _address_run(self, start: int, end: int) -> None:
        """``X100Y10``, ``G0``, ``Z-5``, ``R6=...``: address words, several may be packed
        into one name token; the numbers may carry a sign."""
        tokens = self.tokens
        position = start
        while True:
            match = _ADDRESS.match(self.code, position)
            if match is None or match.group(1).upper() not in EQUALS_ADDRESSES | {"N", "R", "O"}:
                break
            while self.index < len(tokens) and tokens[self.index][3] <= match.end():
                self.index += 1
            inside = self.index < len(tokens) and tokens[self.index][2] < match.end()
            letter, number = match.group(1).upper(), float(match.group(2))
            if not inside and self.at("="):
                self.take()
                self._equals(self.code[position:match.end()].upper().replace("+", ""), position)
                return
            if letter == "R":
                raise _Fail(f"R{match.group(2)} without '=': an R parameter is assigned with R{match.group(2)}=value", position)
            if letter == "N":
                if self.block.number is not None or self.block.items or self.block.label or number != int(number):
                    raise _Fail("the block number N must start the block", position)
                self.block.number = int(number)  # N10G0X0: the block number written against the next word
            else:
                self.block.items.append(Item("word", position, match.end(), letter, number))
            position = match.end()
            if not inside:
                return
        inside = self.index < len(tokens) and tokens[self.index][2] < position
        if inside:
            rest = self.code[position:tokens[self.index][3]].upper()
            if self.peek(1)[1] == "=" and rest in EQUALS_ADDRESSES:
                self.index += 2
                self._equals(rest, position)
                return
        raise _Fail(f"'{self.code[position:max(end, position + 1)]}' is not an address word", position)

    def _equals(self, name: str, start: int) -> None:
        """``NAME=value``: an address with an expression, an R parameter or a variable."""
        if re.fullmatch(r"R\d+", name):
            value = self.expression()
            self.block.items.append(Item("assign", start, self.last_end(), name, value, extra=ir.Var(name)))
            return
        if name in EQUALS_ADDRESSES or re.fullmatch(r"[A-Z]\d", name):
            mode = None
            if (self.at("AC") or self.at("IC")) and self.peek(1)[1] == "(":
                mode = self.take()[1].upper()
                self.expect("(")
                value = self.expression()
                self.expect(")")
            else:
                value = self.expression()
            self.block.items.append(Item("word", start, self.last_end(), name, value, mode))
            return
        value = self.expression()
        self.block.items.append(Item("assign", start, self.last_end(), name, value, extra=ir.Var(name)))

    def _indexed(self, name: str, start: int) -> None:
        """``NAME[i,j]=value`` (array element, system variable, ``G[1]=``, ``M[R1]=``)."""
        indexes = self._index_list()
        if not self.at("="):
            raise _Fail(f"'=' expected after {name}[...]", self.peek()[2])
        self.take()
        if name in OPTION_PAIRS and self.at("("):
            args, _spans = self._arguments()  # OSCTRL[Z]=(options set, options reset)
            self.block.items.append(Item("command", start, self.last_end(), name, args=args))
            return
        value = self.expression()
        self.block.items.append(Item("assign", start, self.last_end(), name, value, extra=indexed_var(name, indexes)))

    def _index_list(self) -> list:
        self.expect("[")
        indexes = [self.expression()]
        while self.at(","):
            self.take()
            indexes.append(self.expression())
        self.expect("]")
        return indexes

    def _call(self, name: str, start: int) -> None:
        args, spans = self._arguments()
        if name in PREDEFINED_PROCEDURES:
            self.block.items.append(Item("command", start, self.last_end(), name, args=args))
        elif name in MOTION_PROCEDURES:
            self.block.items.append(Item("unsupported", start, self.last_end(), f"{name}(...) ({MOTION_PROCEDURES[name]})"))
        else:
            self.block.items.append(Item("call", start, self.last_end(), name, args=args, arg_spans=spans))

    def _arguments(self) -> tuple[list, list]:
        """A bracketed argument list; an empty position is None (the callee sees 0)."""
        self.expect("(")
        args, spans = [], []
        if self.at(")"):
            self.take()
            return args, spans
        while True:
            if self.at(",") or self.at(")"):
                args.append(None)
                position = self.peek()[2]
                spans.append((position, position))
            else:
                first = self.peek()[2]
                args.append(self.expression())
                spans.append((first, self.last_end()))
            if self.at(","):
                self.take()
                continue
            self.expect(")")
            return args, spans

    def _bare_name(self, name: str, start: int, end: int) -> None:
        """A name alone: a path command of G group 1, a known command that needs no
        modelling, or a subprogram call."""
        if name in PATH_COMMANDS:
            self.block.items.append(Item("word", start, end, name))
        elif name in IGNORED_COMMANDS or name in MODAL_COMMANDS:
            self.block.items.append(Item("command", start, end, name))
        elif name in FRAME_COMMANDS:
            self.block.items.append(Item("unsupported", start, end, f"{name} (a frame turned to the workpiece or the tool)", True))
        else:
            self.block.items.append(Item("call", start, end, name))

    def last_end(self) -> int:
        return self.tokens[self.index - 1][3] if self.index else 0

    def rest(self, start: int, what: str, changes_state: bool = False) -> None:
        """Consume the rest of the block as one construct that is read but not modelled
        (``changes_state``: it may write an offset, a frame or tool data: ``value`` True)."""
        self.index = len(self.tokens)
        self.block.items.append(Item("unsupported", start, len(self.code.rstrip()), what, changes_state))

    # ------------------------------------------------------------------ keywords

    def _kw_if(self, start: int) -> None:
        condition = self.expression()
        if self.peek()[1].upper() in ("GOTOF", "GOTOB", "GOTO", "GOTOC"):
            direction = self.take()[1].upper()
            label = self._label_target()
            self.block.items.append(Item("goto", start, self.last_end(), direction, label, condition=condition))
            return
        self.block.items.append(Item("if", start, self.last_end(), condition=condition))

    def _label_target(self):
        kind, text, start, _end = self.take()
        if kind == "name":
            return text.upper()
        if kind == "number":
            return text
        raise _Fail("a label or block number must follow the jump", start)

    def _goto(self, start: int, direction: str) -> None:
        label = self._label_target()
        self.block.items.append(Item("goto", start, self.last_end(), direction, label))

    def _kw_gotof(self, start):
        self._goto(start, "GOTOF")

    def _kw_gotob(self, start):
        self._goto(start, "GOTOB")

    def _kw_goto(self, start):
        self._goto(start, "GOTO")

    def _kw_gotoc(self, start):
        self._goto(start, "GOTOC")

    def _simple(self, kind: str, start: int) -> None:
        self.block.items.append(Item(kind, start, self.last_end()))

    def _kw_else(self, start):
        self._simple("else", start)

    def _kw_endif(self, start):
        self._simple("endif", start)

    def _kw_endwhile(self, start):
        self._simple("endwhile", start)

    def _kw_endfor(self, start):
        self._simple("endfor", start)

    def _kw_loop(self, start):
        self._simple("loop", start)

    def _kw_endloop(self, start):
        self._simple("endloop", start)

    def _kw_ret(self, start):
        self._simple("ret", start)

    def _kw_endproc(self, start):
        self._simple("ret", start)

    def _kw_while(self, start):
        condition = self.expression()
        self.block.items.append(Item("while", start, self.last_end(), condition=condition))

    def _kw_until(self, start):
        condition = self.expression()
        self.block.items.append(Item("until", start, self.last_end(), condition=condition))

    def _kw_for(self, start):
        kind, name, name_start, _ = self.take()
        if kind != "name":
            raise _Fail("FOR needs a counter variable", name_start)
        self.expect("=")
        first = self.expression()
        self.expect("TO")
        last = self.expression()
        self.block.items.append(Item("for", start, self.last_end(), name.upper(), first, args=[last]))

    def _kw_repeat(self, start):
        if self.done():
            self._simple("repeat", start)
            return
        self._repeat_section("REPEAT", start, "a start label, an end label (or none) and P=count", 2)

    def _kw_repeatb(self, start):
        self._repeat_section("REPEATB", start, "the label of one block and P=count", 1)

    def _repeat_section(self, keyword: str, start: int, takes: str, most_labels: int) -> None:
        """``REPEAT A [B] [P=n]`` / ``REPEATB A [P=n]``: the labels (upper case) and the
        count expression (None: once)."""
        labels = []
        while not self.done() and self.peek()[0] == "name" and self.peek(1)[1] != "=":
            labels.append(self.take()[1].upper())
        count = None
        if self.at("P"):
            self.take()
            self.expect("=")
            count = self.expression()
        if not self.done() or not 1 <= len(labels) <= most_labels:
            raise _Fail(f"{keyword} takes {takes}", self.peek()[2] if not self.done() else start)
        self.block.items.append(Item("repeat_section", start, self.last_end(), keyword, labels, args=[count]))

    def _kw_case(self, start):
        selector = self.expression()
        self.expect("OF")
        branches, default = [], None
        while not self.done():
            if self.at("DEFAULT"):
                self.take()
                self.expect(self.peek()[1].upper() if self.peek()[1].upper() in ("GOTOF", "GOTOB", "GOTO") else "GOTOF")
                default = self._label_target()
                continue
            value = self._primary()
            direction = self.take()[1].upper()
            if direction not in ("GOTOF", "GOTOB", "GOTO", "GOTOC"):
                raise _Fail("CASE: each constant is followed by GOTOF/GOTOB and a label", start)
            branches.append((value, self._label_target()))
        self.block.items.append(Item("case", start, self.last_end(), value=selector, args=branches, extra=default))

    def _kw_def(self, start):
        kind, type_name, type_start, _ = self.take()
        type_name = type_name.upper()
        if type_name in ("NCK", "CHAN", "LUD", "GUD", "PGUD"):
            kind, type_name, type_start, _ = self.take()
            type_name = type_name.upper()
        if type_name not in DEF_TYPES:
            raise _Fail(f"DEF: '{type_name}' is not a type (REAL, INT, BOOL, CHAR, STRING, AXIS, FRAME)", type_start)
        if type_name == "STRING" and self.at("["):
            self._index_list()
        variables = []
        while True:
            kind, name, name_start, _ = self.take()
            if kind != "name":
                raise _Fail("DEF: a variable name expected", name_start)
            dimensions = self._index_list() if self.at("[") else None
            value = None
            if self.at("="):
                self.take()
                if self.at("SET") or self.at("("):
                    self.rest(start, "array initialisation")
                    self.block.items.pop()
                    value = None
                    variables.append((name.upper(), dimensions, None, name_start))
                    break
                value = self.expression()
            variables.append((name.upper(), dimensions, value, name_start))
            if not self.at(","):
                break
            self.take()
        if not self.done():
            raise _Fail("DEF: ',' or end of block expected", self.peek()[2])
        self.block.items.append(Item("def", start, self.last_end(), type_name, variables))

    def _kw_proc(self, start):
        kind, name, name_start, _ = self.take()
        if kind != "name":
            raise _Fail("PROC needs a program name", name_start)
        parameters = []
        if self.at("("):
            self.take()
            while not self.at(")"):
                by_reference = False
                if self.at("VAR"):
                    self.take()
                    by_reference = True
                kind, type_name, type_start, _ = self.take()
                if type_name.upper() not in DEF_TYPES:
                    raise _Fail(f"PROC parameter: '{type_name}' is not a type", type_start)
                if type_name.upper() == "STRING" and self.at("["):
                    self._index_list()
                kind, parameter, parameter_start, _ = self.take()
                if kind != "name":
                    raise _Fail("PROC: a parameter name expected", parameter_start)
                if self.at("["):
                    self._index_list()
                parameters.append((type_name.upper(), parameter.upper(), by_reference))
                if self.at(","):
                    self.take()
                elif not self.at(")"):
                    raise _Fail("PROC: ',' or ')' expected", self.peek()[2])
            self.take()
        while not self.done() and self.peek()[0] == "name":
            self.take()  # SAVE, DISPLOF, SBLOF
        self.block.items.append(Item("proc", start, self.last_end(), name.upper(), parameters))

    def _kw_mcall(self, start):
        if self.done():
            self.block.items.append(Item("mcall", start, self.last_end()))
            return
        kind, name, _name_start, _ = self.take()
        if kind != "name":
            raise _Fail("MCALL needs a subprogram name or nothing", self.tokens[self.index - 1][2])
        args, spans = self._arguments() if self.at("(") else ([], [])
        self.block.items.append(Item("mcall", start, self.last_end(), name.upper(), args=args, arg_spans=spans))

    def _frame(self, start):
        keyword = self.tokens[self.index - 1][1].upper()
        words = []
        while not self.done() and self.peek()[0] == "name":
            word_start = self.peek()[2]
            before = len(self.block.items)
            self._item()
            words.extend(self.block.items[before:])
            del self.block.items[before:]
            if words and words[-1].kind != "word":
                raise _Fail(f"{keyword} takes axis words", word_start)
        self.block.items.append(Item("frame", start, self.last_end(), keyword, words))

    _kw_trans = _kw_atrans = _kw_rot = _kw_arot = _kw_rots = _kw_arots = _frame
    _kw_mirror = _kw_amirror = _kw_scale = _kw_ascale = _frame

    def _kw_workpiece(self, start):
        args, spans = self._arguments() if self.at("(") else ([], [])
        self.block.items.append(Item("workpiece", start, self.last_end(), "WORKPIECE", args=args, arg_spans=spans))

    def _kw_msg(self, start):
        if self.at("("):
            self._arguments()
        self._simple("msg", start)

    def _kw_setal(self, start):
        args, _ = self._arguments()
        self.block.items.append(Item("setal", start, self.last_end(), value=args[0] if args else 0.0))

    def _kw_stopre(self, start):
        self.block.items.append(Item("command", start, self.last_end(), "STOPRE"))

    def _kw_save(self, start):
        self.block.items.append(Item("command", start, self.last_end(), "SAVE"))

    _kw_displof = _kw_displon = _kw_save

    def _synchronised(self, start):
        writes = any(name in self.code.upper() for name in _OFFSET_VARIABLES)  # an axis offset or a frame changed beside the program
        self.rest(start, "a synchronised action (WHEN/WHENEVER/EVERY ... DO)", writes)

    _kw_when = _kw_whenever = _kw_every = _kw_id = _kw_ids = _kw_do = _kw_cancel = _synchronised

    def _kw_extcall(self, start):
        self.rest(start, "EXTCALL (a program run from external storage)")

    def _kw_isocall(self, start):
        self.rest(start, "ISOCALL (an ISO-dialect program)")

    def _kw_call(self, start):
        self.rest(start, "CALL (an indirect subprogram call)")

    _kw_pcall = _kw_call

    def _kw_ctabdef(self, start):
        self.rest(start, "a curve table definition")

    _kw_ctabend = _kw_ctabdef

    def _kw_redef(self, start):
        self.rest(start, "REDEF (a definition-file attribute)")

    def _kw_spos(self, start):
        self.rest(start, "SPOS (spindle positioning)")

    _kw_sposa = _kw_spos

    def _indirect_code(self, start):
        """``G[1]=5``, ``M=3``, ``M[R1]=3``, ``T="NAME"``, ``D=2``: an address assigned."""
        letter = self.tokens[self.index - 1][1].upper()
        if self.at("["):
            self._index_list()
            self.expect("=")
            self.expression()
            self.block.items.append(Item("unsupported", start, self.last_end(), f"{letter}[...]= (a code chosen by an index)"))
            return
        self.expect("=")
        value = self.expression()
        self.block.items.append(Item("word", start, self.last_end(), letter, value))

    _kw_m = _kw_g = _kw_t = _kw_d = _kw_h = _kw_s = _kw_f = _indirect_code

    def _kw_extern(self, start):
        self.index = len(self.tokens)
        self.block.items.append(Item("command", start, len(self.code.rstrip()), "EXTERN"))

    # ------------------------------------------------------------------ expressions

    def expression(self):
        if self.peek()[0] == "number" and self.peek(1)[1] in _AFTER_AN_OPERAND:
            return self._unary()  # a literal argument (CYCLE81(15, 0, 2, -5)): no operator level has anything to take
        return self._binary_level(0)

    # ':' chains frames (CTRANS(..):CROT(..)) and binds loosest
    _LEVELS = ((":",), ("OR",), ("XOR",), ("AND",), ("B_OR", "B_XOR", "B_AND"), ("==", "<>", "<", ">", "<=", ">="), ("<<",),
               ("+", "-"), ("*", "/", "DIV", "MOD"))

    def _binary_level(self, level: int):
        if level == len(self._LEVELS):
            return self._unary()
        left = self._binary_level(level + 1)
        operators = self._LEVELS[level]
        while self.peek()[0] in ("op", "name") and self.peek()[1].upper() in operators:
            operator = self.take()[1].upper()
            right = self._binary_level(level + 1)
            left = _combine(operator, left, right)
        return left

    def _unary(self):
        self.terms += 1
        if self.terms > MAX_TERMS:
            raise _Fail(terms_message(MAX_TERMS), self.peek()[2])
        if self.depth >= MAX_NESTING:
            raise _Fail(nesting_message(MAX_NESTING), self.peek()[2])
        self.depth += 1
        try:
            return self._signed()
        finally:
            self.depth -= 1

    def _signed(self):
        if self.at("<<"):
            self.take()
            self._unary()
            return ir.Var("(<<)")  # conversion to a string: not a number the checker follows
        if self.at("-"):
            self.take()
            operand = self._unary()
            return -operand if type(operand) is float else ir.Unary("-", operand)
        if self.at("+"):
            self.take()
            return self._unary()
        if self.at("NOT"):
            self.take()
            return ir.Binary("EQ", self._unary(), 0.0)
        return self._primary()

    def _primary(self):
        kind, text, start, end = self.take()
        if kind == "number":
            return _number(text)
        if kind == "string":
            return text[1:-1]
        if kind == "op" and text == "(":
            value = self.expression()
            self.expect(")")
            return value
        if kind == "name":
            upper = text.upper()
            if upper in ("TRUE", "FALSE"):
                return 1.0 if upper == "TRUE" else 0.0
            if self.at("(") and (self.peek()[2] == end or upper in PREDEFINED_FUNCTIONS):
                args, _ = self._arguments()
                return _function(upper, args, start)
            if self.at("["):  # in an expression a bracket after a name is its index, blanks or not
                return indexed_var(upper, self._index_list())
            return ir.Var(upper)
        if kind == "end":
            raise _Fail("the expression ends too early", start)
        raise _Fail(f"unexpected '{text}' in an expression", start)


def _number(text: str) -> float:
    if "EX" in text.upper():
        mantissa, exponent = text.upper().split("EX")
        return float(f"{mantissa}e{int(exponent)}")
    return float(text)


def _combine(operator: str, left, right):
    if operator in _COMPARE:
        return ir.Binary(_COMPARE[operator], left, right)
    if operator in ("+", "-", "*", "/", "MOD", "AND", "OR", "XOR"):
        return ir.Binary(operator, left, right)
    if operator == "DIV":
        return ir.Func("FIX", (ir.Binary("/", left, right),))
    return ir.Var(f"({operator})")  # string concatenation, bit operations, a frame chain: an unknown value


def _function(name: str, args: list, start: int):
    if name in FUNCTIONS and len(args) == 1 and args[0] is not None:
        return ir.Func(FUNCTIONS[name], (args[0],))
    if name in TWO_ARGUMENT_FUNCTIONS and len(args) == 2 and None not in args:
        return ir.Func(TWO_ARGUMENT_FUNCTIONS[name], tuple(args))
    if name == "POT" and len(args) == 1 and args[0] is not None:
        return ir.Binary("*", args[0], args[0])
    if name in ("AC", "IC") and len(args) == 1:
        return args[0]
    return ir.Var(f"{name}()")  # a function the checker does not evaluate: an unknown value


def indexed_var(name: str, indexes: list):
    """An array element or system variable with indexes. Literal indexes give a fixed
    name (``$TC_DP6[1,1]``); a computed single index gives an indirect reference."""
    if all(type(index) is float for index in indexes):
        return ir.Var(f"{name}[{','.join(f'{index:g}' for index in indexes)}]")
    if all(isinstance(index, ir.Var) and type(index.name) is str and index.name in _AXIS_NAMES or type(index) is float
           for index in indexes):
        return ir.Var(f"{name}[{','.join(index.name if isinstance(index, ir.Var) else f'{index:g}' for index in indexes)}]")
    if len(indexes) == 1:
        return ir.Var(indexes[0], prefix=f"{name}[")
    return ir.Var(f"{name}[?]")


_AXIS_NAMES = frozenset({"X", "Y", "Z", "A", "B", "C", "TR", "FI", "RT", "MI", "SC"})

# Commands read alone that change nothing the checks model.
IGNORED_COMMANDS = frozenset({
    "STOPRE", "SOFT", "BRISK", "DRIVE", "FFWON", "FFWOF", "COMPOF", "COMPON", "COMPCAD", "COMPCURV", "UPATH", "SPATH",
    "CPRECON", "CPRECOF", "TRAFOOF", "TRAORI", "TRANSMIT", "TRACYL", "PAROTOF", "TOROTOF", "TCOABS", "TCOFR", "CFC", "CFTCP", "CFIN", "SBLOF", "SBLON", "DISPLOF", "DISPLON", "SAVE",
    "WAITM", "WAITS", "WAITMC", "SPCON", "SPCOF", "NORM", "KONT", "KONTC", "KONTT", "FNORM", "FLIN", "FCUB", "BNAT",
    "BTAN", "BAUTO", "ENAT", "ETAN", "EAUTO", "ACC", "OFFN", "CUT2D", "CUT2DF", "CUT3DC", "CDON", "CDOF", "CDOF2",
    "G64", "G60", "G9", "G601", "G602", "G603", "G641", "G642", "G643", "G644", "G645", "ORIWKS", "ORIMKS", "ORIAXES",
    "ORIVECT", "DIAMON", "DIAMOF", "DIAM90", "DIAMCYCOF", "FGROUP", "LIMS", "GWPSON", "GWPSOF", "TMON", "TMOF",
    "SUPA", "PTP", "CP", "PTPG0", "DYNNORM", "DYNPOS", "DYNROUGH", "DYNSEMIFIN", "DYNFINISH", "STARTFIFO", "STOPFIFO",
    "FIFOCTRL", "AXNAME", "REPOSA", "REPOSL", "REPOSQ", "REPOSH", "CORROF", "SYNFCT", "DELDTG", "TRAILOF", "LEADOF",
})
# Commands that turn the frame to the workpiece or the tool (not modelled: nothing after them is
# placed on the blank; their ...OF cancels are ignored, as the turn is not followed anyway).
FRAME_COMMANDS = frozenset({"PAROT", "TOROT", "TOROTX", "TOROTY", "TOROTZ", "TOFRAME", "TOFRAMEX", "TOFRAMEY", "TOFRAMEZ"})
# Commands that set modal state the lowering turns into IR (handled there by name).
MODAL_COMMANDS = frozenset({"CFC"})
# Path commands written as names, modal in G group 1 with G0-G3: CIP, an arc through the
# intermediate point I1= J1= K1=; CT, an arc tangent to the previous path element.
PATH_COMMANDS = {"CIP": "arc_through", "CT": "arc_tangent"}

# Predefined procedures called with arguments that do not move axes or change what the
# checks model (file access, waiting, messages, tables, protection zones).
PREDEFINED_PROCEDURES = frozenset({
    "WAITS", "WAITM", "WAITMC", "WAITE", "WRITE", "READ", "DELETE", "ISFILE", "FILEDATE", "FILETIME", "FILESIZE",
    "FILESTAT", "FILEINFO", "MMC", "SETM", "CLEARM", "GETSELT", "SETPIECE", "CTABDEF", "CTABEND", "CTABDEL",
    "FGROUP", "FCTDEF", "PUTFTOC", "PUTFTOCF", "CPROTDEF", "NPROTDEF", "CPROT", "NPROT", "STOPRE", "TRAORI", "TRANSMIT",
    "TRACYL", "TRAANG", "TRAFOOF", "DIAMCYCOF", "SPCON", "SPCOF", "WALIMON", "WALIMOF", "G25", "G26", "LIMS",
    "ACTBLOCNO", "STARTFIFO", "ROUNDUP", "SBLOF", "DISPLOF",
})
# Settings of an axis written as a pair in parentheses, the options to set and those to
# reset (oscillation control): read, with no modelled effect.
OPTION_PAIRS = frozenset({"OSCTRL"})
# Predefined procedures that move axes or the spindle in ways the checker does not model.
MOTION_PROCEDURES = {
    "SPOS": "spindle positioning", "SPOSA": "spindle positioning", "POS": "positioning axis motion",
    "POSA": "positioning axis motion", "OSCILL": "oscillation", "PRESETON": "actual value setting",
    "TANGON": "tangential control", "COUPON": "axis coupling", "LEADON": "master value coupling",
    "EGON": "electronic gear", "SPIPOS": "spindle positioning",
}
