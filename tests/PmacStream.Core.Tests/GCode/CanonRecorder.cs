using PmacStream.GCode;

namespace PmacStream.Core.Tests.GCode;

/// <summary>Keeps every canonical call the interpreter makes, in order, for tests to read.</summary>
internal sealed class CanonRecorder : ICanonicalMoves
{
    /// <summary>The states blocks started from.</summary>
    public List<CanonStart> Starts { get; } = [];

    /// <summary>The steps of cycles and reference returns.</summary>
    public List<HostMove> Steps { get; } = [];

    /// <summary>The blocks' motions.</summary>
    public List<CanonMotion> Motions { get; } = [];

    public void StartBlock(in CanonStart start) => Starts.Add(start);

    public void Step(in HostMove step) => Steps.Add(step);

    public void Motion(in CanonMotion motion) => Motions.Add(motion);

    /// <summary>The settings and code calls, as text ("ChangeTool 2 M6"), in the order made.</summary>
    public List<string> Calls { get; } = [];

    public void SelectTool(int tool) => Calls.Add($"SelectTool {tool}");

    public void ChangeTool(int tool, in CanonCode code) => Calls.Add($"ChangeTool {tool} {Text(code)}");

    public void SetSpindleSpeed(double speed) => Calls.Add(FormattableString.Invariant($"SetSpindleSpeed {speed}"));

    public void SetFeedRate(double feed) => Calls.Add(FormattableString.Invariant($"SetFeedRate {feed}"));

    public void Spindle(SpindleCall call, in CanonCode code) => Calls.Add($"Spindle {call} {Text(code)}");

    public void Coolant(CoolantCall call, in CanonCode code) => Calls.Add($"Coolant {call} {Text(code)}");

    public void ProgramStop(ProgramStopCall call, in CanonCode code) => Calls.Add($"ProgramStop {call} {Text(code)}");

    public void Dwell(double seconds) => Calls.Add(FormattableString.Invariant($"Dwell {seconds}"));

    public void UseToolLengthOffset(int mode, int number) => Calls.Add($"UseToolLengthOffset {mode} {number}");

    public void Code(in CanonCode code) => Calls.Add($"Code {Text(code)}");

    private static string Text(in CanonCode code)
    {
        var text = code.Letter + code.Number.ToString(System.Globalization.CultureInfo.InvariantCulture);
        foreach (var w in code.Words)
        {
            text += FormattableString.Invariant($" {w.Letter}{w.Value}");
        }

        return text;
    }
}
