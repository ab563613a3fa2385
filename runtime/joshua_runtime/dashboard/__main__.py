"""Entry point of `python -m joshua_runtime.dashboard`."""

from joshua_runtime.dashboard.cli import main
from joshua_runtime.process_end import end_process

end_process(main())  # without the DDS library's teardown: a third of the dashboard's stop
