namespace PmacStream.IntegrationTests.Plc;

/// <summary>
/// The motor forward/reverse relay circuit as an electrician describes it, written independently of the rungs: stop and
/// thermal trip drop both contactors; a running contactor holds itself in; from rest a start button pulls in its
/// contactor (forward wins if both are held, as the scan order decides); the other direction is locked out until
/// stopped. Inputs SB1 bit 0, SB2 bit 1, SB3 bit 2, KR bit 3; outputs KM1 bit 0, KM2 bit 1.
/// </summary>
internal readonly record struct RelayMotor(bool Forward, bool Reverse)
{
    public const int Sb1 = 1, Sb2 = 2, Sb3 = 4, Kr = 8;

    public RelayMotor Step(long inputs)
    {
        bool Held(int bit) => (inputs & bit) != 0;
        if (Held(Sb1) || Held(Kr))
        {
            return default;
        }

        if (Forward || Reverse)
        {
            return this;
        }

        if (Held(Sb2))
        {
            return new RelayMotor(true, false);
        }

        return Held(Sb3) ? new RelayMotor(false, true) : default;
    }

    public long Outputs => (Forward ? 1 : 0) | (Reverse ? 2 : 0);
}

/// <summary>Exhaustive check of every press/release sequence up to a length against <see cref="RelayMotor"/>.</summary>
internal sealed class MotorCircuitExplorer(IPlcRig rig, int maxLength)
{
    private static readonly int[] Buttons = [RelayMotor.Sb1, RelayMotor.Sb2, RelayMotor.Sb3, RelayMotor.Kr];

    public long Steps { get; private set; }

    public long Starts { get; private set; }

    public long SealIns { get; private set; }

    public long Stops { get; private set; }

    public long Trips { get; private set; }

    public long ReversalsAfterStop { get; private set; }

    public long RefusedReversals { get; private set; }

    public void Run()
    {
        rig.SetInputs(0);
        rig.Scan();
        rig.Outputs.Should().Be(0, "nothing runs after power-up with no button pressed");
        Explore(0, 0, default, 0, new int[maxLength]);
    }

    private void Explore(int depth, long inputs, RelayMotor model, long lastOutputs, int[] path)
    {
        if (depth == maxLength)
        {
            return;
        }

        var snapshot = rig.Snapshot();
        var stoppedSince = lastOutputs == 0;
        for (var e = 0; e < Buttons.Length * 2; e++)
        {
            rig.Restore(snapshot);
            long bit = Buttons[e / 2];
            var press = e % 2 == 0;
            var now = press ? inputs | bit : inputs & ~bit;
            rig.SetInputs(now);
            rig.Scan();
            var outputs = rig.Outputs;
            var next = model.Step(now);
            path[depth] = e;
            Steps++;
            string Where() => Describe(path, depth + 1);
            Check(outputs == next.Outputs, () => $"the relay circuit gives KM1={next.Forward} KM2={next.Reverse} but the PLC gave outputs {outputs} after {Where()}");

            // The behaviours the issue names, stated directly on the program's outputs.
            Check((outputs & 3) != 3, () => $"forward and reverse are never on together ({Where()})");
            if ((now & (RelayMotor.Sb1 | RelayMotor.Kr)) != 0)
            {
                Check(outputs == 0, () => $"stop or thermal trip drops both contactors ({Where()})");
                if (lastOutputs != 0)
                {
                    if ((now & RelayMotor.Kr) != 0)
                    {
                        Trips++;
                    }
                    else
                    {
                        Stops++;
                    }
                }
            }
            else
            {
                if (lastOutputs == 0 && (now & RelayMotor.Sb2) != 0)
                {
                    Check(outputs == 1, () => $"start forward ({Where()})");
                    Starts++;
                }

                if (lastOutputs != 0)
                {
                    Check(outputs == lastOutputs, () => $"a running contactor holds itself in ({Where()})");
                    if ((now & (RelayMotor.Sb2 | RelayMotor.Sb3)) == 0)
                    {
                        SealIns++;
                    }
                }

                if (lastOutputs == 1 && (now & RelayMotor.Sb3) != 0)
                {
                    RefusedReversals++;
                }
            }

            if ((outputs & 2) != 0 && (lastOutputs & 2) == 0)
            {
                Check(stoppedSince, () => $"reverse only pulls in from rest ({Where()})");
                if (path.Take(depth).Any(x => x == 0))
                {
                    ReversalsAfterStop++;
                }
            }

            Explore(depth + 1, now, next, outputs, path);
        }
    }

    private static void Check(bool ok, Func<string> message)
    {
        if (!ok)
        {
            throw new Xunit.Sdk.XunitException(message());
        }
    }

    private static string Describe(int[] path, int length) =>
        string.Join(", ", path.Take(length).Select(e => (e % 2 == 0 ? "press " : "release ") + (new[] { "SB1", "SB2", "SB3", "KR" })[e / 2]));
}
