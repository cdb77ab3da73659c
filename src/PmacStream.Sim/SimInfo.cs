namespace PmacStream.Sim;

/// <summary>Identification the simulator answers to <c>VERSION</c> and <c>TYPE</c>.</summary>
public static class SimInfo
{
    /// <summary>Firmware version string, as a Turbo PMAC 2 answers it.</summary>
    public const string Version = "1.947";
}
