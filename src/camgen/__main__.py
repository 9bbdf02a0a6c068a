import sys

from camgen.cli import main

sys.exit(main())
