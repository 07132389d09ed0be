pytest_plugins = ['wurde_testing.fixtures']
