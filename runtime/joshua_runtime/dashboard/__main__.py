"""Entry point of `python -m joshua_runtime.dashboard`."""

from joshua_runtime.dashboard.cli import main
from joshua_runtime.process_end import end_process

end_process(main())  # without the interpreter's teardown of DDS and OpenCV: half of the dashboard's stop
