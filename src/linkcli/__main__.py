"""`python -m linkcli` runs the command line."""

from linkcli.cli import main

if __name__ == "__main__":
    main()
