from camgen.cli import entry

entry()
