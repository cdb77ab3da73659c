namespace PmacStream.Sim;

/// <summary>A move or dwell calculated ahead of execution, waiting in the lookahead queue or executing.</summary>
internal sealed class Segment
{
    public MoveKind Kind;
    public double[] Start = new double[CoordinateSystem.AxisCount];
    public double[] End = new double[CoordinateSystem.AxisCount];
    public double Duration;
    public double Remaining;
    public double Length;
    public double Feed;
    public bool BlocksCalculation;

    // The acceleration time (s) in force when the move was calculated: max(TA, 2 TS), 0 for rapids and dwells.
    public double Acceleration;
    public List<(int Index, double Value)>? Sync;

    // Arc geometry (circle moves only): plane axes, centre in plane, start angle, signed sweep, radius at the start and the end.
    public int A1;
    public int A2;
    public int An;
    public double C1;
    public double C2;
    public double StartAngle;
    public double Sweep;
    public double Radius;
    public double EndRadius;
    public double StartTime;
    public int SourceLine;

    // The synchronous assignment of the tracking variable fired at this segment's start: a block's first move.
    public bool BlockStart;

    public bool IsArc => Kind is MoveKind.Circle1 or MoveKind.Circle2;

    public void PositionAt(double fraction, double[] into)
    {
        for (var i = 0; i < into.Length; i++)
        {
            into[i] = Start[i] + ((End[i] - Start[i]) * fraction);
        }

        if (IsArc && fraction < 1)
        {
            var a = StartAngle + (Sweep * fraction);
            var r = Radius + ((EndRadius - Radius) * fraction);
            into[A1] = C1 + (r * Math.Cos(a));
            into[A2] = C2 + (r * Math.Sin(a));
        }
    }
}
