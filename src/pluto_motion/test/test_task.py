"""The go_to handle (pluto_motion.task) without processes: polled to its result, cancelled (the
module told once), timed out (FAILED with the reason), an ended task keeping its result."""

from __future__ import annotations

from pluto_motion.task import Task, TaskResult


def _task(results: list[TaskResult], timeout: float | None = None) -> tuple[Task, list[str]]:
    told: list[str] = []
    answers = iter(results)
    return Task(lambda: (next(answers, TaskResult.UNKNOWN), 'why'), lambda: told.append('stop'),
                timeout=timeout), told


def test_polled_until_it_ends() -> None:
    task, told = _task([TaskResult.UNKNOWN, TaskResult.UNKNOWN, TaskResult.SUCCEEDED])
    assert not task.is_task_complete() and task.result() is TaskResult.UNKNOWN
    assert not task.is_task_complete()
    assert task.is_task_complete() and task.result() is TaskResult.SUCCEEDED
    task.cancel()                                  # an ended task keeps its result
    assert task.result() is TaskResult.SUCCEEDED and told == []


def test_cancel_tells_the_module_once() -> None:
    task, told = _task([TaskResult.UNKNOWN])
    task.cancel()
    task.cancel()
    assert task.is_task_complete() and task.result() is TaskResult.CANCELED and told == ['stop']


def test_timeout_fails_and_stops() -> None:
    task, told = _task([], timeout=0.0)
    assert task.wait(1.0) is TaskResult.FAILED
    assert task.reason == 'timed out' and told == ['stop']
