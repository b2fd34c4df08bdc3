"""Idempotent FreeCAD properties (SheetMetal / freecad.gears pattern).

Each object class lists its properties once as :class:`Prop` records. The
same list serves creation and migration: :func:`ensure` adds what an object
lacks (an older document) and leaves existing values alone, so it is safe to
call on every restore. Names are PascalCase and never change once released.
"""
import FreeCAD as App

EDIT, READONLY, HIDDEN = 0, 1, 2
# Property status bits (App::PropertyType): 8 = Output (setting it does not
# touch the object, so results written during a recompute do not mark it for
# another recompute); 32 = NoPersist is NOT used: results are saved.
PROP_OUTPUT = 8


class Prop:
    __slots__ = ("type", "name", "group", "doc", "default", "mode", "output")

    def __init__(self, type_, name, group, doc, default=None, mode=EDIT, output=False):
        self.type, self.name, self.group, self.doc = type_, name, group, doc
        self.default, self.mode, self.output = default, mode, output


def ensure(obj, props):
    """Add the missing properties of `props` to `obj`; returns the names added."""
    added = []
    have = set(obj.PropertiesList)
    for p in props:
        if p.name not in have:
            obj.addProperty(p.type, p.name, p.group, p.doc, PROP_OUTPUT if p.output else 0)
            if p.default is not None:
                if p.type == "App::PropertyEnumeration":
                    setattr(obj, p.name, list(p.default))
                    setattr(obj, p.name, p.default[0])
                else:
                    setattr(obj, p.name, p.default)
            added.append(p.name)
        obj.setEditorMode(p.name, p.mode)
    return added


def quantity_mm(q):
    """A length property (Quantity or float in mm) as float millimetres."""
    return float(q.Value) if hasattr(q, "Value") else float(q)


def quantity_deg(q):
    return float(q.getValueAs("deg")) if hasattr(q, "getValueAs") else float(q)


def set_if_changed(obj, name, value):
    """Assign only when the value differs (avoids needless touches and undo entries)."""
    cur = getattr(obj, name)
    try:
        cur_v = cur.Value if hasattr(cur, "Value") else cur
        if isinstance(value, App.Units.Quantity):
            value_v = value.Value
        else:
            value_v = value
        if cur_v == value_v:
            return False
    except Exception:
        pass
    setattr(obj, name, value)
    return True
