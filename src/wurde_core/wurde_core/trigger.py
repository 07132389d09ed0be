"""Triggers: let ``run_update`` return only when new data or info arrived (guide 5.3).

Every object of one trigger must receive something before the trigger fires (AND); any one of
several triggers registered with a CommsManager makes ``run_update`` return (OR).  The manager
does not say which trigger fired, as in the guide.
"""

from __future__ import annotations

from typing import Protocol


class RobotObject(Protocol):
    """What a trigger reads of an object: how many events it has taken in so far."""

    _arrivals: int


class Trigger:
    """A set of objects that must all have new data or info for the trigger to fire."""

    def __init__(self, *objects: 'RobotObject') -> None:
        """A trigger over ``objects``.

        :param objects: RobotObjects (registered as consumers, or suppliers of requests); each
            counts once.
        """
        self._objects: list[RobotObject] = []
        self._seen: dict[int, int] = {}
        for obj in objects:
            self.add(obj)

    def add(self, obj: 'RobotObject') -> None:
        """Add an object (the guide's "register an object with the trigger"); only what it
        takes in from now on counts.

        :param obj: a RobotObject; one already in the trigger is ignored.
        """
        if any(o is obj for o in self._objects):
            return
        self._objects.append(obj)
        self._seen[id(obj)] = obj._arrivals

    register_object = add

    def remove(self, obj: 'RobotObject') -> None:
        """Take ``obj`` out of the trigger.

        :param obj: a RobotObject (nothing happens when it is not in the trigger).
        """
        self._objects = [o for o in self._objects if o is not obj]
        self._seen.pop(id(obj), None)

    @property
    def objects(self) -> tuple['RobotObject', ...]:
        """The objects of this trigger, in the order they were added."""
        return tuple(self._objects)

    def ready(self) -> bool:
        """Whether every object received something since the trigger last fired."""
        return bool(self._objects) and all(
            obj._arrivals != self._seen[id(obj)] for obj in self._objects)

    def fire(self) -> bool:
        """If ready, consume the arrivals and return True; otherwise False."""
        if not self.ready():
            return False
        for obj in self._objects:
            self._seen[id(obj)] = obj._arrivals
        return True
