"""A scriptable WURDE module for cross-process tests.

Usage: ``peer.py NAME [options for parse_options]``.  Runs the WURDE loop (sleep 10 ms) and reads
commands from stdin, one per line; answers each with ``OK <command> [result]`` (or
``ERR <command> <error>``) and prints ``STATE <name>`` whenever its run state changes.

Commands (``S`` is a stream name):
  supply IFACE S [queue]        register a supplier      consume IFACE S [queue]  a consumer
  set_info S MEMBER VALUE       info.MEMBER.set_value    publish_info S
  publish S COUNT               publish COUNT data events (Foo: ranges=[i]); result: how many went
  wait_subscribers S            until the data channel has a subscriber    wait_acked S
  lock S MEMBER|* MODE [OWNER]  set a lock               refused S  requests refused so far
  requests S                    print each pending request's set members
  data S                        print pending data events (ranges[0] of Foo)
  quit                          leave the loop
  stream S                      from now on publish one event per loop, ranges=[loop number]

Every run state the module enters is printed from a state callback (``manager.on_state``); the
callbacks for Reset and Restart replace the defaults, so the peer returns to Run at once.  With
``WURDE_PEER_PLAIN=1`` in its environment the peer registers no callbacks and gets the manager's
default behaviours; it prints ``STARTED <pid>`` when it (re)starts.  With ``WURDE_PEER_LINGER=1``
it stays alive after ``BYE`` (its clean-up) until the line ``exit``, like a module whose exit is slow.
"""

from __future__ import annotations

import ast
import os
import queue
import sys
import threading

from wurde_core import CommsManager, LockMode, RunState
from wurde_core.interfaces import robot_object_class


def main() -> int:
    manager = CommsManager(sys.argv[1])
    manager.parse_options([sys.argv[0], *sys.argv[2:]])
    manager.set_sleep(0.01)
    objects = {}
    commands: queue.Queue[str] = queue.Queue()

    def read_stdin() -> None:
        for line in sys.stdin:
            commands.put(line.strip())
        commands.put('quit')

    threading.Thread(target=read_stdin, daemon=True).start()
    if os.environ.get('WURDE_PEER_PLAIN') != '1':
        for state in (RunState.IDLE, RunState.RESET, RunState.RESTART, RunState.RUN):
            manager.on_state(state, lambda state=state: print(f'STATE {state.name}', flush=True))
    running, loops, streaming = True, 0, []
    while running:
        if manager.run_update() == RunState.QUIT:
            print('STATE QUIT', flush=True)
            break
        if loops == 0:
            print(f'STARTED {os.getpid()}', flush=True)
            print('STATE RUN', flush=True)
        for obj in streaming:
            obj.data.ranges = [float(loops)]
            obj.publish_data()
        loops += 1
        while not commands.empty():
            line = commands.get()
            if not line:
                continue
            words = line.split()
            if words[0] == 'stream' and len(words) == 2 and words[1] in objects:
                streaming.append(objects[words[1]])
                print(f'OK {line}', flush=True)
                continue
            try:
                result = execute(manager, objects, words)
            except Exception as exc:  # report every failure to the test, keep running
                print(f'ERR {line} {type(exc).__name__}: {exc}', flush=True)
                continue
            if result == 'quit':
                running = False
                break
            print(f'OK {line} {result if result is not None else ""}'.rstrip(), flush=True)
    manager.clean_up()
    print('BYE', flush=True)
    if os.environ.get('WURDE_PEER_LINGER') == '1':   # stay until told, as a slow exit would
        while commands.get() != 'exit':
            pass
    return 0


def execute(manager: CommsManager, objects: dict, words: list[str]) -> object:
    verb = words[0]
    if verb == 'quit':
        return 'quit'
    if verb in ('supply', 'consume'):
        obj = robot_object_class(words[1])(words[2])
        if 'queue' in words[3:]:
            obj.set_queue_mode(True)
        (manager.register_supplier if verb == 'supply' else manager.register_consumer)(obj)
        objects[words[2]] = obj
        return None
    obj = objects[words[1]]
    if verb == 'set_info':
        getattr(obj.info, words[2]).set_value(ast.literal_eval(' '.join(words[3:])))
        return None
    if verb == 'publish_info':
        return obj.publish_info()
    if verb == 'publish':
        sent = 0
        for i in range(int(words[2])):
            if 'ranges' in obj.data.field_names():
                obj.data.ranges = [float(i)]
            sent += bool(obj.publish_data())
        return sent
    if verb == 'wait_subscribers':
        obj.wait_for_peers(20)
        return obj.peers()
    if verb == 'wait_acked':
        return obj.wait_delivered(20)
    if verb == 'lock':
        member = '' if words[2] == '*' else words[2]
        obj.set_lock(member, LockMode[words[3]], words[4] if len(words) > 4 else '')
        return None
    if verb == 'refused':
        return obj.refused_requests
    if verb == 'requests':
        found = []
        while obj.get_next_request():
            message = obj.requests.ros_message()
            found.append(f'{message.header.source}:' + ','.join(
                f'{f}={getattr(obj.requests, f).get_value()!r}' for f in message.set_fields))
        return ' '.join(found) or '-'
    if verb == 'data':
        found = []
        while obj.get_next_data():
            found.append(str(obj.data.ranges[0]))
        return ' '.join(found) or '-'
    raise ValueError(f'unknown command {verb}')


if __name__ == '__main__':
    sys.exit(main())
