import sys

try:
    from .cli import main
except KeyboardInterrupt:  # Ctrl-C while the command line itself is imported: no traceback either
    sys.stderr.write("yoyogait: interrupted (SIGINT)\n")
    sys.exit(130)

sys.exit(main())
