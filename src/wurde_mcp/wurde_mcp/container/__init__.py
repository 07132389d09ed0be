"""Several managed modules in one process (issue 39): the ``<container>`` of an MCP config.

:mod:`.host` is the container program (the process that runs the modules in threads);
:mod:`.member` is the MCP's side (the container process and each contained module, the latter
with the interface of :class:`wurde_mcp.process.ModuleProcess`, so the supervisor starts, stops,
restarts and watches a contained module as it does a process).
"""
