#!/usr/bin/python3
"""Opens a RenderDoc capture with RenderDoc's replay (python3-renderdoc, /usr/bin/python3 only),
prints its marker regions and named resources, and fails unless every expected pass shows as
a marker region and every expected resource carries its name.

usage: list_markers.py CAPTURE.rdc --passes NAME... --resources NAME...
"""
import argparse
import os
import sys

import renderdoc as rd


def marker_names(actions, sfile, depth=0, out=None):
    out = [] if out is None else out
    for action in actions:
        if action.flags & rd.ActionFlags.PushMarker:
            name = action.GetName(sfile)
            out.append(name)
            print("  " * depth + "marker: " + name)
        marker_names(action.children, sfile, depth + 1, out)
    return out


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("capture")
    parser.add_argument("--passes", nargs="*", default=[])
    parser.add_argument("--resources", nargs="*", default=[])
    args = parser.parse_args()

    rd.InitialiseReplay(rd.GlobalEnvironment(), [])
    capture = rd.OpenCaptureFile()
    result = capture.OpenFile(args.capture, "", None)
    if result != rd.ResultCode.Succeeded:
        sys.exit(f"cannot open {args.capture}: {result}")
    if not capture.LocalReplaySupport():
        sys.exit(f"{args.capture} cannot be replayed on this machine")
    result, controller = capture.OpenCapture(rd.ReplayOptions(), None)
    if result != rd.ResultCode.Succeeded:
        sys.exit(f"cannot replay {args.capture}: {result}")

    markers = marker_names(controller.GetRootActions(), controller.GetStructuredFile())
    resources = {resource.name for resource in controller.GetResources()}

    missing_passes = [name for name in args.passes if name not in markers]
    missing_resources = [name for name in args.resources if name not in resources]
    if missing_passes or missing_resources:
        print("named resources: " + ", ".join(sorted(resources)))
        print(f"missing marker regions: {missing_passes}; missing resource names: {missing_resources}")
        code = 1
    else:
        print(f"ok: {len(markers)} marker regions, all {len(args.passes)} passes and "
              f"{len(args.resources)} resources found")
        code = 0
    sys.stdout.flush()
    # The verdict is printed first and the replay's own teardown, not needed to exit, is skipped:
    # RenderDoc's replay on lavapipe now and then segfaults (check_capture.sh runs it again).
    os._exit(code)


if __name__ == "__main__":
    main()
