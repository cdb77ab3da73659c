namespace PmacStream.WinForms;

/// <summary>Entry point of the HMI.</summary>
internal static class Program
{
    [STAThread]
    private static void Main()
    {
        ApplicationConfiguration.Initialize();
        Application.Run(new Form { Text = "PmacStream" });
    }
}
