"""Frozen dataclasses that cost less to define: `@record` in place of `@dataclass(frozen=True)`.

Why: Python 3.11's dataclass compiles each method it writes (__init__, __repr__, __eq__, __hash__,
__setattr__, __delattr__) with an exec of its own, about 0.4 ms per frozen class: 25 ms of a small
job's 0.17 s, over the 40 classes it defines. A record is the dataclass itself (dataclasses.fields,
replace, asdict and pickling work on it) with one compiled method, __init__, which runs per instance;
the others are functions shared by every record, over the names of its fields. They give what
dataclass's would: the same repr, equality (same class, equal field tuples), hash (of the tuple;
none with eq=False, which keeps identity), and FrozenInstanceError on assignment or deletion.
"""

from __future__ import annotations

import dataclasses
import operator
import reprlib
from typing import Any, Callable, TypeVar

try:
    from typing import dataclass_transform  # Python >= 3.11: type checkers read records as dataclasses
except ImportError:  # pragma: no cover - Python 3.10
    def dataclass_transform(**_: Any) -> Callable[[Any], Any]:
        return lambda decorator: decorator

T = TypeVar("T", bound=type)

_MISSING = dataclasses.MISSING


@dataclass_transform(frozen_default=True, field_specifiers=(dataclasses.field,))
def record(cls: T | None = None, /, *, eq: bool = True) -> Any:
    """@dataclass(frozen=True, eq=eq) with its methods made as the module docstring says."""

    def wrap(cls: T) -> T:
        return _make(cls, eq)

    return wrap if cls is None else wrap(cls)


def _make(cls: T, eq: bool) -> T:
    own = dict(cls.__dict__)  # what the class body defines: kept, as dataclass keeps it
    if "__setattr__" in own or "__delattr__" in own:
        raise TypeError(f"cannot overwrite __setattr__ or __delattr__ of a frozen record: {cls.__name__}")
    documented = bool(own.get("__doc__"))
    if not documented:  # else dataclass reads object's signature (a tokenizer regex compiled: 7 ms)
        cls.__doc__ = "-"
    dataclasses.dataclass(cls, init=False, repr=False, eq=False, match_args=True)
    fields = dataclasses.fields(cls)
    if "__init__" not in own:
        cls.__init__ = _init_fn(cls, fields, hasattr(cls, "__post_init__"))
    if not documented:  # dataclass's text, from the signature of the __init__ it would have written
        import inspect  # noqa: PLC0415 - dataclasses has it loaded already

        cls.__doc__ = cls.__name__ + str(inspect.signature(cls)).replace(" -> None", "")
    if "__repr__" not in own:
        cls.__repr__ = _repr_fn(tuple(f.name for f in fields if f.repr))
    if eq and "__eq__" not in own:
        cls.__eq__ = _eq_fn(_key_fn(tuple(f.name for f in fields if f.compare)))
    # A class that writes __eq__ gets __hash__ = None from Python itself: not a hash of its own.
    explicit_hash = "__hash__" in own and not (own["__hash__"] is None and "__eq__" in own)
    if eq and not explicit_hash:
        hashed = tuple(f.name for f in fields if (f.compare if f.hash is None else f.hash))
        cls.__hash__ = _hash_fn(_key_fn(hashed))
    cls.__setattr__ = _frozen_setattr
    cls.__delattr__ = _frozen_delattr
    return cls


def _init_fn(cls: type, fields: tuple[dataclasses.Field, ...], post_init: bool) -> Callable[..., None]:
    """The one compiled method: arguments as dataclass writes them, each stored in the instance's
    __dict__ (what object.__setattr__ does for a field, which has no descriptor, at a fifth of the cost
    of its call: a 24-field result costs ~2 us instead of ~10)."""
    scope: dict[str, Any] = {"__factory": _MISSING}
    args, body = ["self"], ["    __d = self.__dict__"]
    for f in fields:
        if f.kw_only:
            raise TypeError(f"{cls.__name__}.{f.name}: keyword-only fields are not supported by record")
        value = f.name
        if f.default_factory is not _MISSING:
            scope[f"__factory_{f.name}"] = f.default_factory
            if f.init:
                args.append(f"{f.name}=__factory")
                value = f"__factory_{f.name}() if {f.name} is __factory else {f.name}"
            else:
                value = f"__factory_{f.name}()"
        elif f.default is not _MISSING:
            scope[f"__default_{f.name}"] = f.default
            if f.init:
                args.append(f"{f.name}=__default_{f.name}")
            else:
                value = f"__default_{f.name}"
        elif f.init:
            args.append(f.name)
        else:
            continue  # no value until __post_init__ gives one, as with dataclass
        body.append(f"    __d[{f.name!r}] = {value}")
    if post_init:
        body.append("    self.__post_init__()")
    source = (f"def __create_fn__({', '.join(scope)}):\n"
              f"  def __init__({', '.join(args)}):\n" + "\n".join("  " + line for line in body)
              + "\n  return __init__")
    local: dict[str, Any] = {}
    exec(source, {}, local)  # noqa: S102 - source built above from field names only
    init = local["__create_fn__"](**scope)
    init.__qualname__ = f"{cls.__qualname__}.__init__"
    init.__annotations__ = {**{f.name: f.type for f in fields if f.init}, "return": None}
    return init


def _key_fn(names: tuple[str, ...]) -> Callable[[Any], tuple[Any, ...]]:
    """The tuple of these fields of an instance (always a tuple, whatever their number)."""
    if not names:
        return lambda _self: ()
    if len(names) == 1:
        one = operator.attrgetter(names[0])
        return lambda self: (one(self),)
    return operator.attrgetter(*names)


def _eq_fn(key: Callable[[Any], tuple[Any, ...]]) -> Callable[[Any, Any], Any]:
    def __eq__(self: Any, other: Any) -> Any:
        if other.__class__ is self.__class__:
            return key(self) == key(other)
        return NotImplemented

    return __eq__


def _hash_fn(key: Callable[[Any], tuple[Any, ...]]) -> Callable[[Any], int]:
    def __hash__(self: Any) -> int:
        return hash(key(self))

    return __hash__


def _repr_fn(names: tuple[str, ...]) -> Callable[[Any], str]:
    @reprlib.recursive_repr()
    def __repr__(self: Any) -> str:
        inner = ", ".join(f"{name}={getattr(self, name)!r}" for name in names)
        return f"{self.__class__.__qualname__}({inner})"

    return __repr__


def _frozen_setattr(self: Any, name: str, value: Any) -> None:
    raise dataclasses.FrozenInstanceError(f"cannot assign to field {name!r}")


def _frozen_delattr(self: Any, name: str) -> None:
    raise dataclasses.FrozenInstanceError(f"cannot delete field {name!r}")
