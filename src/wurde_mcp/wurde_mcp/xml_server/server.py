"""The xmlServer's socket server: Mobotware's line protocol over TCP, one turn at a time.

AU Robot Servers, "Interface description": a server has one port (24919..24930) and up to ten
clients; on connect it sends the XML declaration and its opening root tag, then answers each
command line.  :class:`XmlServer` never blocks longer than asked and starts no thread: the module's
loop calls :meth:`XmlServer.serve` every turn, which accepts, reads, answers at most
``lines_per_turn`` lines per client, runs the due pushes and sends what each socket takes.

No client can hurt the others or the server: its input and output buffers are bounded (a too long
line is dropped, a client that does not read its output is disconnected), a silent client is closed
after ``idle_timeout``, a malformed line is answered with a warning and a socket error or a failing
command handler ends only that client's session or command.

Commands are handlers registered by name (:meth:`XmlServer.add_command`): ``help``, ``q`` (``quit``,
``exit``), ``push``, ``varpush``, ``var`` and ``pt`` (a robot controller's odometry pose, never
answered: :mod:`.pose_command`) are built in, and AURS's other commands (:mod:`.standard`); the
robot's module may add more.  An interface to another server (:mod:`.interface`) has its socket
watched by the same selector (:meth:`XmlServer.watch`), and pollers run every turn
(:meth:`XmlServer.add_poller`), so one thread still serves everything.
"""

from __future__ import annotations

import dataclasses
import logging
import selectors
import socket
import time
from collections.abc import Callable, Sequence
from pathlib import Path

from .command import Command, CommandError, closing, escape, help_block, parse_command, reply
from .command_table import CommandTable, Handler
from .host import Watcher
from .pose_command import PT_HELP, PoseCommand
from .push import EventPush, TimePush
from .push_commands import PushCommands, push_help, varpush_help
from .session import TOO_LONG, Session
from .settings import PORTS, ServerSettings, ServerStats
from .standard import install_standard
from .user_vars import UserVariables
from .var_command import VAR_HELP, VarCommand
from .var_log import VarLog
from .variables import VariablePool

__all__ = ['Handler', 'PORTS', 'ServerSettings', 'ServerStats', 'XmlServer']

_log = logging.getLogger(__name__)

#: How long an ending session may take to send its last output before it is closed anyway (s).
_LINGER_S = 2.0
#: Connections accepted per turn at most (the rest wait in the listen queue for the next turn).
_ACCEPTS_PER_TURN = 16


class XmlServer:
    """Mobotware's xmlServer protocol over one pool of variables.

    Life cycle: construct (no I/O), :meth:`start` (bind and listen; may raise OSError),
    :meth:`serve` every turn (never raises because of what a client sends), :meth:`close`
    (idempotent).  Single-threaded: call these from one thread (:attr:`stats` and
    :attr:`client_count` may be read from another).
    """

    def __init__(self, pool: VariablePool, settings: ServerSettings | None = None) -> None:
        self.pool = pool
        self.settings = settings if settings is not None else ServerSettings()
        self._stats = ServerStats()
        self._commands = CommandTable()
        self._sessions: list[Session] = []
        self._selector: selectors.BaseSelector | None = None
        self._listener: socket.socket | None = None
        self._port = self.settings.port
        self._hostname = ''
        self._closed = False
        self._pollers: list[Callable[[float], None]] = []
        self._turn_start = time.monotonic()
        #: Seconds between the starts of the last two turns (``alive``).
        self.turn_gap = 0.0
        s = self.settings
        #: The variables clients made (``var X="v"``, copies from another server).
        self.user_vars = UserVariables(pool)
        #: The var logfile (``var log``).
        self.var_log = VarLog(pool, Path(s.data_path) / f'{s.name}.var.log')
        pushes = PushCommands(pool, min_period=s.min_push_period, max_pushes=s.max_pushes,
                              is_command=lambda name: name in self._commands, clock=time.monotonic)
        self.add_command('push', pushes, 'Time push: run a command every t seconds',
                         help_text=push_help(s.min_push_period, s.max_pushes), group='server')
        self.add_command('q', self._quit, 'Close connection to this client by server',
                         group='server')
        self.add_command('help', self.help_handler, 'This help (help CMD: help on command CMD)',
                         group='server')
        self.add_command('quit', self._quit, 'The same as q', group='server')
        self.add_command('exit', self._quit, 'The same as q', group='server')
        self.add_command('var', VarCommand(pool, self.user_vars, self.var_log),
                         'Get, set and list variables',
                         help_text=VAR_HELP, group='var')
        self.add_command('varPush', pushes, 'Update push: run a command on updates of a structure',
                         help_text=varpush_help(s.max_pushes), group='var')
        self.add_command('pt', PoseCommand(pool), 'Odometry pose from a robot controller: no reply',
                         help_text=PT_HELP, group='pt')
        self.modules = install_standard(self, pushes)
        self.add_poller(lambda now: self.var_log.poll())

    # ---- the API ------------------------------------------------------------------------------

    def add_command(self, name: str, handler: Handler, help_line: str, *,
                    help_text: str | None = None, group: str | None = None) -> None:
        """Add command ``name`` (any case): ``handler(client, command)`` returns its reply lines.

        ``help_line`` is its line in ``help``; ``<name help/>`` answers a help block of
        ``help_text`` (or of ``help_line`` when None) without calling the handler.  Commands of one
        ``group`` (default: the name) share one line of ``help``'s list of commands.  A handler may
        end the client's session (:meth:`Session.end`); an exception in it is answered with an
        ``error`` reply and the session goes on.

        :raises ValueError: ``name`` is not a tag name or is taken.
        """
        self._commands.add(name, handler, help_line, help_text=help_text, group=group)

    def remove_command(self, name: str) -> None:
        """Remove command ``name`` (any case; absent: nothing)."""
        self._commands.remove(name)

    def command_groups(self) -> dict[str, list[str]]:
        """The commands by group, as ``help`` lists them (a copy)."""
        return self._commands.groups()

    def add_poller(self, poller: Callable[[float], None]) -> None:
        """Call ``poller(now)`` every turn (monotonic s)."""
        self._pollers.append(poller)

    def remove_poller(self, poller: Callable[[float], None]) -> None:
        if poller in self._pollers:
            self._pollers.remove(poller)

    def watch(self, sock: socket.socket, watcher: Watcher, events: int) -> None:
        """Have the selector call ``watcher.on_event(mask)`` for ``events`` on ``sock``."""
        assert self._selector is not None, 'watch() before start()'
        try:
            self._selector.modify(sock, events, watcher)
        except KeyError:
            self._selector.register(sock, events, watcher)

    def unwatch(self, sock: socket.socket) -> None:
        if self._selector is not None:
            try:
                self._selector.unregister(sock)
            except (KeyError, ValueError):
                pass

    @property
    def port(self) -> int:
        """The port listened on (after :meth:`start`; before, the port asked for)."""
        return self._port

    @property
    def client_count(self) -> int:
        """Clients connected now."""
        return sum(not s.ending for s in self._sessions)

    @property
    def stats(self) -> ServerStats:
        """A copy of the counters."""
        return dataclasses.replace(self._stats)

    def start(self) -> None:
        """Bind and listen.

        :raises OSError: the address cannot be bound (the port is in use, say).
        :raises RuntimeError: started before or closed.
        """
        if self._listener is not None or self._closed:
            raise RuntimeError('XmlServer.start(): already started or closed')
        listener = socket.socket(socket.AF_INET6 if ':' in self.settings.host else socket.AF_INET,
                                 socket.SOCK_STREAM)
        try:
            listener.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            listener.bind((self.settings.host, self.settings.port))
            listener.listen(self.settings.max_clients + 4)
            listener.setblocking(False)
        except OSError:
            listener.close()
            raise
        self._listener = listener
        self._port = listener.getsockname()[1]
        self._hostname = socket.gethostname()
        self._selector = selectors.DefaultSelector()
        self._selector.register(listener, selectors.EVENT_READ, None)

    def serve(self, timeout: float) -> None:
        """One turn: wait at most ``timeout`` s for activity, then accept, read, answer, push, send.

        :raises RuntimeError: not started, or closed.
        """
        if self._selector is None or self._closed:
            raise RuntimeError('XmlServer.serve(): start() first')
        now = time.monotonic()
        self.turn_gap, self._turn_start = now - self._turn_start, now
        try:
            events = self._selector.select(self._wait(now, timeout))
        except InterruptedError:
            events = []
        for key, mask in events:
            if key.data is None:
                self._accept(time.monotonic())
            elif not isinstance(key.data, Session):
                self._event(key.data, mask)
            elif mask & selectors.EVENT_READ:
                self._guarded(key.data, self._receive)
        now = time.monotonic()
        for poller in list(self._pollers):
            try:
                poller(now)
            except Exception:           # a failing poller must not take the server down
                _log.exception('poller %r failed', poller)
        for session in list(self._sessions):
            self._guarded(session, lambda s: self._turn(s, now))

    def close(self) -> None:
        """Send every client the closing root tag, close the sockets (idempotent)."""
        if self._closed:
            return
        self._closed = True
        self.modules.close()
        self.var_log.close()
        bye = closing(self.settings.name).encode()
        for session in list(self._sessions):
            try:                         # a last try: what the socket takes now
                if session.ending or session.queue(bye, self.settings.send_buffer + len(bye)):
                    session.flush()
            except OSError:
                pass
            self._drop(session)
        if self._selector is not None:
            self._selector.close()
        if self._listener is not None:
            self._listener.close()

    # ---- one turn -----------------------------------------------------------------------------

    def _wait(self, now: float, timeout: float) -> float:
        """How long select() may wait: 0 when lines wait or a variable an event push watches was
        updated since (the module's loop took a stream in), else until the next push is due."""
        wait = max(0.0, timeout)
        for session in self._sessions:
            if session.ending:
                continue
            if session.has_line():
                return 0.0
            for push in session.pushes:
                if isinstance(push, TimePush):
                    wait = min(wait, max(0.0, push.next_due - now))
                elif isinstance(push, EventPush) and push.pending(self.pool):
                    return 0.0
        return wait

    @staticmethod
    def _event(watcher: Watcher, mask: int) -> None:
        try:
            watcher.on_event(mask)
        except Exception:
            _log.exception('watcher %r failed', watcher)

    def _guarded(self, session: Session, step: Callable[[Session], None]) -> None:
        """Run ``step``; a socket error (or any failure) closes only this session."""
        if session.closed:
            return
        try:
            step(session)
        except OSError as exc:
            _log.debug('client %s: %s', session.address, exc)
            self._drop(session)
        except Exception:            # a bug must not take the server down: log, drop the client
            _log.exception('client %s: closed after an internal error', session.address)
            self._drop(session)

    def _accept(self, now: float) -> None:
        assert self._listener is not None and self._selector is not None
        for _ in range(_ACCEPTS_PER_TURN):
            try:
                sock, address = self._listener.accept()
            except (BlockingIOError, InterruptedError):
                return
            except OSError as exc:           # ECONNABORTED, EMFILE: try again next turn
                _log.warning('accept: %s', exc)
                return
            sock.setblocking(False)
            if self.client_count >= self.settings.max_clients:
                self._refuse(sock)
                continue
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            self._stats.accepted += 1
            session = Session(sock, address, self._stats.accepted, now)
            self._sessions.append(session)
            self._selector.register(sock, selectors.EVENT_READ, session)
            greeting = ('<?xml version="1.0" encoding="UTF-8"?>\n'
                        f'<{self.settings.name} name="{self.settings.name}" '
                        f'version="{escape(self.settings.version)}">\n')
            self._guarded(session, lambda s: self._send(s, [greeting]))

    def _refuse(self, sock: socket.socket) -> None:
        self._stats.refused += 1
        n = self.settings.max_clients
        try:
            sock.send(reply('error', [('warning', f'too many clients: {self.client_count} are '
                                                  f'connected (max {n})')]).encode())
        except OSError:
            pass
        sock.close()

    def _receive(self, session: Session) -> None:
        if session.ending or session.eof or session.has_line():
            return
        if not session.receive(self.settings.max_line):
            session.eof = True           # handle what came, then end
        else:
            session.last_activity = time.monotonic()
        self._stats.peak_input = max(self._stats.peak_input, session.buffered_input)

    def _turn(self, session: Session, now: float) -> None:
        if not session.ending:
            self._handle_lines(session)
        if not session.ending and not session.closed:
            if session.eof and not session.has_line():
                self._finish(session, now)
            else:
                self._run_pushes(session, now)
        if session.closed:
            return
        if not session.ending and now - session.last_activity > self.settings.idle_timeout:
            self._stats.idle_disconnects += 1
            self._send(session, [reply('error', [('warning', 'idle for '
                                                  f'{self.settings.idle_timeout:g} s: closing')])])
            self._finish(session, now)
        if session.closed:
            return
        session.flush(now)
        if session.ending and (not session.pending_output or now > session.end_deadline):
            self._drop(session)
        else:
            self._watch(session)

    def _handle_lines(self, session: Session) -> None:
        s = self.settings
        for _ in range(s.lines_per_turn):
            line = session.next_line(s.max_line)
            if line is None:
                return
            if line is TOO_LONG:
                self._stats.dropped_long_lines += 1
                self._send(session, [reply('error', [('warning', f'line longer than {s.max_line} '
                                                                 'bytes: dropped')])])
            elif isinstance(line, str) and line.strip(' \t\r'):
                self._stats.lines += 1
                self._send(session, self._execute(session, line))
            if session.closed:
                return
            if session.end_requested:
                self._finish(session, time.monotonic())
                return

    def _execute(self, session: Session, line: str) -> list[str]:
        try:
            command = parse_command(line)
        except CommandError as exc:
            self._stats.malformed += 1
            return [reply('error', [('warning', f'malformed command: {exc}')])]
        return self._commands.dispatch(session, command)

    def _run_pushes(self, session: Session, now: float) -> None:
        for push in list(session.pushes):
            if push in session.pushes and push.poll(now, self.pool):
                self._send(session, self._commands.dispatch(session, push.command))
                if session.closed:
                    return
                if session.end_requested:
                    self._finish(session, now)
                    return

    def _send(self, session: Session, lines: Sequence[str]) -> None:
        """Queue ``lines``; a client whose output passes send_buffer is disconnected."""
        if not lines or session.closed:
            return
        if not session.queue(''.join(lines).encode('utf-8', errors='replace'),
                             self.settings.send_buffer):
            self._stats.slow_disconnects += 1
            _log.info('client %s: disconnected, %d bytes of output not read', session.address,
                      session.pending_output)
            self._drop(session)
            return
        self._stats.peak_output = max(self._stats.peak_output, session.pending_output)

    def _finish(self, session: Session, now: float) -> None:
        """End ``session``: the closing root tag, then close once sent (or after a linger)."""
        if session.ending:
            return
        bye = closing(self.settings.name).encode()
        if not session.queue(bye, self.settings.send_buffer + len(bye)):
            self._drop(session)
            return
        session.ending = True
        session.pushes.clear()
        session.end_deadline = now + min(_LINGER_S, self.settings.idle_timeout)

    def _watch(self, session: Session) -> None:
        """Select on reading while the session reads, on writing while output waits."""
        assert self._selector is not None
        events = (0 if session.ending or session.eof else selectors.EVENT_READ) | \
            (selectors.EVENT_WRITE if session.pending_output else 0)
        if not events:
            events = selectors.EVENT_READ
        if self._selector.get_key(session.sock).events != events:
            self._selector.modify(session.sock, events, session)

    def _drop(self, session: Session) -> None:
        if session.closed:
            return
        session.closed = True
        session.pushes.clear()
        if session in self._sessions:
            self._sessions.remove(session)
        if self._selector is not None:
            try:
                self._selector.unregister(session.sock)
            except (KeyError, ValueError):
                pass
        session.sock.close()

    # ---- built-in commands --------------------------------------------------------------------

    def _quit(self, client: Session, command: Command) -> list[str]:
        client.end()
        return []

    def help_handler(self, client: Session, command: Command) -> list[str]:
        """``help``: the seed's main help, or ``help CMD``: the help of command CMD."""
        for key, value in command.args:
            entry = self._commands.help_of(key)
            if entry is not None and not value:
                return help_block(entry.name.upper(), entry.help_text or entry.help_line,
                                  command.tag)
        s = self.settings
        lines = ['----- Main help:',
                 f'This is {s.name}-{s.version} a server in the AU Robot Server series',
                 f'running on host {self._hostname or socket.gethostname()} port {self.port}',
                 f'with {self.client_count} of at most {s.max_clients} clients connected and '
                 f'{len(self.pool.names())} variables.',
                 '---',
                 'Available commands (from currently loaded modules):']
        lines += self._commands.listing()
        lines += ['---',
                  r'A command should be packed in XML brackets and must be terminated by a \n '
                  '(newline)',
                  'e.g.:',
                  '<var list/>   or if you are lazy just:',
                  'var list',
                  '---']
        return help_block('server help', '\n'.join(lines), command.tag)
