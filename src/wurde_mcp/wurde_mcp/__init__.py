"""The Master Control Program: a lifecycle supervisor node that starts modules from mcp-config and
mcp-mappings, watches heartbeats, restarts and assigns streams (issue: wurde_mcp)."""
