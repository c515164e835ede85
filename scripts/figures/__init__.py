"""The tables scripts/tables.py writes into the docs, by the kind of results they are made
from; `results` reads those results and says when and where they ran."""
