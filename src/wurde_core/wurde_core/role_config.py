"""RoleConfiguration: the role-config file, environment overrides and module options.

Seed: WURDE Programming Guide 5.1.2-5.1.4 and appendix 10.1.1.  The file is ``<wurde-config>``
alone or inside the combined ``<robot>`` file; both the plain and the
``http://wurde.sf.net/wurde-config`` namespaced spellings are read.  Elements: ``data-directory``,
``config-directory``, ``bin-directory`` (``location``), ``log`` (``directory``, ``level``), ``mcp``
(``mcp-config``, ``mcp-mappings``), ``option`` (``name``, ``value``), ``module`` (``name``, with
``option`` children); ``comment`` children are allowed anywhere.  Anything else is refused with
file, line and reason.  The environment (WURDE_CONFIG_DIR, WURDE_DATA_DIR, WURDE_BIN_DIR,
WURDE_MCP_CONFIG, WURDE_MCP_MAPPINGS, WURDE_LOG_LEVEL, WURDE_LOG_DIRECTORY) overrides the file.
"""

from __future__ import annotations

import os
import pathlib
from collections.abc import Mapping

from lxml import etree

from wurde_idl.errors import ConfigError
from wurde_idl.safe_xml import parse_file
from wurde_idl.xml_elements import checked_attributes

from . import module_context

#: Log levels, lowest first (guide 5.1.2); the default is debug.
LOG_LEVELS = ('debug', 'info', 'notice', 'warn', 'error', 'fatal')
#: Default file names (guide 5.1.1 and 6.1-6.2).
DEFAULT_ROLE_CONFIG = 'role-config.xml'
DEFAULT_MCP_CONFIG = 'mcp-config.xml'
DEFAULT_MCP_MAPPINGS = 'mcp-mapping.xml'

_NS = '{http://wurde.sf.net/wurde-config}'
_ENV = {
    'config_directory': 'WURDE_CONFIG_DIR', 'data_directory': 'WURDE_DATA_DIR',
    'bin_directory': 'WURDE_BIN_DIR', 'mcp_config': 'WURDE_MCP_CONFIG',
    'mcp_mappings': 'WURDE_MCP_MAPPINGS', 'log_level': 'WURDE_LOG_LEVEL',
    'log_directory': 'WURDE_LOG_DIRECTORY',
}
_ELEMENTS = {
    'data-directory': ({'location'}, 'data_directory'),
    'config-directory': ({'location'}, 'config_directory'),
    'bin-directory': ({'location'}, 'bin_directory'),
}


def _local(tag: object) -> str | None:
    if not isinstance(tag, str):
        return None  # comment or processing instruction
    return tag[len(_NS):] if tag.startswith(_NS) else tag


class RoleConfiguration:
    """Global settings of one robot role.  ``load()`` reads a file; getters follow guide 5.1.4."""

    def __init__(self, module_name: str = '') -> None:
        """The defaults (guide 5.1.4): directories ``.``, no bin directory, level debug, the
        MCP's files ``mcp-config.xml`` and ``mcp-mapping.xml``, no options.

        :param module_name: the module this configuration is for (:meth:`get_module_name`).
        """
        self.path: str | None = None
        self.module_name = module_name
        self._values: dict[str, str] = {
            'config_directory': '.', 'data_directory': '.', 'bin_directory': '',
            'log_directory': '.', 'log_level': 'debug', 'mcp_config': DEFAULT_MCP_CONFIG,
            'mcp_mappings': DEFAULT_MCP_MAPPINGS,
        }
        self._explicit_log_directory = False
        self._options: dict[str, str] = {}
        self._module_options: dict[str, dict[str, str]] = {}
        self._environ: Mapping[str, str] = os.environ

    # -- loading -------------------------------------------------------------------------------
    def load(self, path: str | os.PathLike[str]) -> 'RoleConfiguration':
        """Read a role-config file (``<wurde-config>`` or ``<robot>`` holding one); what it sets
        replaces what was set before.

        :param path: the file.
        :returns: this configuration.
        :raises ConfigError: naming the file, line and reason when it is wrong.
        """
        path = os.fspath(path)
        root = parse_file(path, root_tag=('wurde-config', 'robot'))
        if _local(root.tag) == 'robot':
            configs = [c for c in root if _local(c.tag) == 'wurde-config']
            if len(configs) != 1:
                raise ConfigError(path, root.sourceline,
                                  f'<robot> must hold exactly one <wurde-config>, found {len(configs)}')
            root = configs[0]
        self._read(path, root)
        self.path = path
        return self

    def _read(self, path: str, root: etree._Element) -> None:
        self._check_attributes(path, root, set(), namespaced_ok=True)
        for node in root:
            tag = _local(node.tag)
            if tag is None or tag == 'comment':
                continue
            if tag in _ELEMENTS:
                allowed, key = _ELEMENTS[tag]
                self._check_attributes(path, node, allowed, required=allowed)
                self._values[key] = node.get('location', '')
            elif tag == 'log':
                self._check_attributes(path, node, {'directory', 'level'})
                if node.get('directory') is not None:
                    self._values['log_directory'] = node.get('directory', '')
                    self._explicit_log_directory = True
                if node.get('level') is not None:
                    self._values['log_level'] = self._level(path, node, node.get('level', ''))
            elif tag == 'mcp':
                self._check_attributes(path, node, {'mcp-config', 'mcp-mappings'})
                for attr, key in (('mcp-config', 'mcp_config'), ('mcp-mappings', 'mcp_mappings')):
                    if node.get(attr) is not None:
                        self._values[key] = node.get(attr, '')
            elif tag == 'option':
                name, value = self._option(path, node)
                self._options[name] = value
            elif tag == 'module':
                self._check_attributes(path, node, {'name'}, required={'name'})
                options = self._module_options.setdefault(node.get('name', ''), {})
                for child in node:
                    child_tag = _local(child.tag)
                    if child_tag is None or child_tag == 'comment':
                        continue
                    if child_tag != 'option':
                        raise ConfigError(path, child.sourceline,
                                          f'unknown tag <{child_tag}> in <module> (only <option>)')
                    name, value = self._option(path, child)
                    options[name] = value
            else:
                raise ConfigError(path, node.sourceline, f'unknown tag <{tag}> in <wurde-config>')
            if tag != 'module':
                for child in node:
                    if _local(child.tag) not in (None, 'comment'):
                        raise ConfigError(path, child.sourceline,
                                          f'unknown tag <{_local(child.tag)}> in <{tag}>')

    def _option(self, path: str, node: etree._Element) -> tuple[str, str]:
        self._check_attributes(path, node, {'name', 'value'}, required={'name', 'value'})
        return node.get('name', ''), node.get('value', '')

    @staticmethod
    def _level(path: str | None, node: etree._Element | None, level: str) -> str:
        if level not in LOG_LEVELS:
            raise ConfigError(path or '<environment>', node.sourceline if node is not None else None,
                              f'log level "{level}" is not one of {", ".join(LOG_LEVELS)}')
        return level

    @staticmethod
    def _check_attributes(path: str, node: etree._Element, allowed: set[str],
                          required: set[str] | frozenset[str] = frozenset(), namespaced_ok: bool = False) -> None:
        checked_attributes(path, node, required=required, optional=allowed, namespaced=namespaced_ok)

    # -- getters (guide 5.1.4) -----------------------------------------------------------------
    def _get(self, key: str) -> str:
        override = self._environ.get(_ENV[key])
        return override if override else self._values[key]

    def get_data_directory(self) -> str:
        """The data directory (``WURDE_DATA_DIR`` overrides the file; default ``.``)."""
        return self._get('data_directory')

    def get_config_directory(self) -> str:
        """The config directory (``WURDE_CONFIG_DIR`` overrides the file; default ``.``)."""
        return self._get('config_directory')

    def get_bin_directory(self) -> str:
        """The bin directory (``WURDE_BIN_DIR`` overrides the file; default empty)."""
        return self._get('bin_directory')

    def get_log_directory(self) -> str:
        """The log directory (``WURDE_LOG_DIRECTORY`` overrides the file; default ``.``)."""
        return self._get('log_directory')

    def explicit_log_directory(self) -> bool:
        """Whether a log directory was configured (file or WURDE_LOG_DIRECTORY)."""
        return self._explicit_log_directory or bool(self._environ.get(_ENV['log_directory']))

    def get_log_level(self) -> str:
        """The lowest level logged (``WURDE_LOG_LEVEL`` overrides the file).

        :raises ConfigError: when the environment names an unknown level.
        """
        return self._level(None, None, self._get('log_level'))

    def get_mcp_config_file(self) -> str:
        """The MCP configuration file, inside the config directory unless absolute."""
        return self._in_config(self._get('mcp_config'))

    def get_mcp_mappings_file(self) -> str:
        """The MCP mappings file, inside the config directory unless absolute."""
        return self._in_config(self._get('mcp_mappings'))

    def get_module_name(self) -> str:
        """The module this configuration was made for."""
        return self.module_name

    def _in_config(self, name: str) -> str:
        return name if os.path.isabs(name) else str(pathlib.Path(self.get_config_directory()) / name)

    def have_option(self, name: str) -> bool:
        """Whether the global option ``name`` is set (file or command line).

        :param name: the option's name (a user option's letter: ``"c"``).
        """
        return name in self._options

    def get_option(self, name: str) -> str:
        """The option's value, or ``"empty"`` when unset (as the guide says).

        :param name: the option's name (a user option's letter: ``"c"``).
        """
        return self._options.get(name, 'empty')

    def set_option(self, name: str, value: str) -> None:
        """Set an option (command-line user options land here).

        :param name: the option's name.
        :param value: its value, as text.
        """
        self._options[name] = value

    def options(self) -> dict[str, str]:
        """Every global option (file and command line), by name."""
        return dict(self._options)

    def module_options(self, module: str) -> dict[str, str]:
        """The options the file gives ``module``, by name.

        :param module: the module's name, as in ``<module name="...">``.
        """
        return dict(self._module_options.get(module, {}))

    def have_module_option(self, module: str, name: str) -> bool:
        """Whether the file gives ``module`` the option ``name``.

        :param module: the module's name, as in ``<module name="...">``.
        :param name: the option's name.
        """
        return name in self._module_options.get(module, {})

    def get_module_option(self, module: str, name: str) -> str:
        """The module's option value, or ``"empty"`` when unset.

        :param module: the module's name, as in ``<module name="...">``.
        :param name: the option's name.
        """
        return self._module_options.get(module, {}).get(name, 'empty')


_global: RoleConfiguration | None = None


def global_configuration() -> RoleConfiguration:
    """The process-wide configuration (the guide's ``g_globalConfiguration``)."""
    global _global
    if module_context.current() is not None:       # a contained module's own (issue 39)
        config = module_context.singleton('configuration', None)
        if config is None:
            config = RoleConfiguration()
            module_context.set_singleton('configuration', config)
        return config
    if _global is None:
        _global = RoleConfiguration()
    return _global


def set_global_configuration(config: RoleConfiguration) -> None:
    """Replace the process-wide configuration (done by ``CommsManager.parse_options``).

    :param config: the configuration :func:`global_configuration` returns from now on.
    """
    global _global
    if not module_context.set_singleton('configuration', config):
        _global = config
