"""Where a diagnostic's results go: its Markdown table, and its summary as JSON, in one folder."""
import json
import os


def write_table(folder, text, summary=None):
    """Writes folder/table.md (text) and, when given, folder/summary.json; makes the folder."""
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "table.md"), "w") as f:
        f.write(text)
    if summary is not None:
        with open(os.path.join(folder, "summary.json"), "w") as f:
            json.dump(summary, f, indent=1)
