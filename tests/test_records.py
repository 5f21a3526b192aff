"""winder.records: a record behaves as @dataclass(frozen=True) does, checked side by side on twins."""

from __future__ import annotations

import dataclasses
import pickle

import numpy as np
import pytest

from winder.records import record


def _twins(eq: bool = True) -> tuple[type, type]:
    """The same class body under @dataclass(frozen=True, eq=eq) and under @record(eq=eq)."""

    def body(deco):
        @deco
        class Part:
            """A part."""

            name: str
            size: float = 2.5
            tags: list = dataclasses.field(default_factory=list)
            note: str = dataclasses.field(default="-", repr=False)
            weight: float = dataclasses.field(default=1.0, compare=False)
            derived: float = dataclasses.field(init=False, default=0.0)

            def double(self) -> float:
                return 2.0 * self.size

        return Part

    return body(dataclasses.dataclass(frozen=True, eq=eq)), body(record(eq=eq))


# Module-level twins: pickle finds classes by their qualified name.
@dataclasses.dataclass(frozen=True)
class Plain:
    """A plain dataclass."""

    a: int
    b: tuple = (1, 2)


@record
class Rec:
    """A record."""

    a: int
    b: tuple = (1, 2)


@record
class Child(Rec):
    """A record extending a record."""

    c: str = "c"


@record
class Checked:
    """A record with __post_init__."""

    low: float
    high: float

    def __post_init__(self) -> None:
        if self.low > self.high:
            raise ValueError("low above high")
        object.__setattr__(self, "span", self.high - self.low)


@pytest.mark.parametrize("args, kwargs", [(("x",), {}), (("x", 3.0), {"tags": [1]}), (("y",), {"note": "n", "weight": 4.0})])
def test_init_repr_eq_hash_match_the_dataclass(args, kwargs):
    made, ours = _twins()
    a, b = made(*args, **kwargs), ours(*args, **kwargs)
    assert dataclasses.astuple(a) == dataclasses.astuple(b)
    assert repr(a).replace("body.<locals>.Part", "Part") == repr(b).replace("body.<locals>.Part", "Part")
    assert ours(*args, **kwargs) == b and not (ours(*args, **kwargs) != b)
    assert (ours(*args, **{**kwargs, "weight": 9.0}) == b) == (made(*args, **{**kwargs, "weight": 9.0}) == a)
    assert (b == a) is False  # another class: NotImplemented both ways, so identity
    with pytest.raises(TypeError):  # a list field: unhashable under both
        hash(b)
    frozen = {**kwargs, "tags": (1,)}
    assert hash(ours(*args, **frozen)) == hash(made(*args, **frozen))  # the same fields' tuple
    assert hash(ours(*args, **frozen)) == hash(ours(*args, **{**frozen, "weight": 7.0}))  # compare=False
    assert ours.__match_args__ == made.__match_args__
    assert [f.name for f in dataclasses.fields(ours)] == [f.name for f in dataclasses.fields(made)]
    assert b.double() == a.double()


def test_each_default_factory_call_is_fresh():
    _, ours = _twins()
    assert ours("x").tags is not ours("x").tags


def test_frozen_like_the_dataclass():
    made, ours = _twins()
    for obj in (made("x"), ours("x")):
        with pytest.raises(dataclasses.FrozenInstanceError):
            obj.size = 3.0
        with pytest.raises(dataclasses.FrozenInstanceError):
            del obj.size
        with pytest.raises(dataclasses.FrozenInstanceError):
            obj.other = 1


def test_signature_errors_like_the_dataclass():
    made, ours = _twins()
    for cls in (made, ours):
        with pytest.raises(TypeError):
            cls()
        with pytest.raises(TypeError):
            cls("x", derived=1.0)  # init=False: not an argument


def test_eq_false_keeps_identity_and_arrays_do_not_compare():
    made, ours = _twins(eq=False)
    a = ours("x", tags=np.arange(3))
    assert a == a and a != ours("x", tags=np.arange(3))
    assert hash(a) == object.__hash__(a)
    assert made.__eq__ is object.__eq__ and ours.__eq__ is object.__eq__


def test_replace_asdict_and_pickle():
    b = Rec(1)
    assert dataclasses.replace(b, a=2) == Rec(2, (1, 2))
    assert dataclasses.asdict(b) == dataclasses.asdict(Plain(1))
    assert pickle.loads(pickle.dumps(b)) == b
    assert dataclasses.is_dataclass(Rec) and dataclasses.is_dataclass(b)


def test_inheritance_and_post_init():
    c = Child(1, c="z")
    assert (c.a, c.b, c.c) == (1, (1, 2), "z") and repr(c) == "Child(a=1, b=(1, 2), c='z')"
    assert c != Rec(1) and Rec(1) != c
    assert Checked(1.0, 3.0).span == 2.0
    with pytest.raises(ValueError, match="low above high"):
        Checked(3.0, 1.0)


def test_docstring_when_the_class_has_none():
    @record
    class Bare:
        a: int
        b: float = 1.0

    @dataclasses.dataclass(frozen=True)
    class Same:
        a: int
        b: float = 1.0

    assert Bare.__doc__ == Same.__doc__.replace("Same", "Bare")


def test_recursive_repr_does_not_loop():
    @record
    class Box:
        """Holds anything."""

        item: list

    box = Box([])
    box.item.append(box)
    assert repr(box) == "test_recursive_repr_does_not_loop.<locals>.Box(item=[...])"


def test_methods_the_class_writes_are_kept_as_dataclass_keeps_them():
    def body(deco):
        @deco
        class Named:
            """Compares by name only."""

            name: str
            size: float = 1.0

            def __repr__(self) -> str:
                return f"<{self.name}>"

            def __eq__(self, other: object) -> bool:
                return isinstance(other, Named) and other.name == self.name

        return Named

    for cls in (body(dataclasses.dataclass(frozen=True)), body(record)):
        a, b = cls("a", 1.0), cls("a", 2.0)
        assert repr(a) == "<a>" and a == b
        # A written __eq__ leaves Python's __hash__ = None, which dataclass replaces by the fields' hash.
        assert hash(a) == hash(cls("a", 1.0)) == hash(("a", 1.0))


def test_a_record_refuses_its_own_setattr_like_the_frozen_dataclass():
    for deco in (dataclasses.dataclass(frozen=True), record):
        with pytest.raises(TypeError):
            @deco
            class Settable:
                """Writes __setattr__."""

                a: int

                def __setattr__(self, name, value):
                    object.__setattr__(self, name, value)
