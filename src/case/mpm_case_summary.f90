!> The summary of a resolved case that --check prints (and logs keep).
submodule (mpm_case) mpm_case_summary
    use mpm_kinds, only: i8
    use mpm_strings, only: int_text, fmt_real, fmt_vector, fmt_box, int_list, text_or, yes_no
    use mpm_case_domain, only: axis_names
    use mpm_case_bodies, only: domain_digits, shape_none, shape_circle, shape_cylinder
    use mpm_case_sites, only: body_site_count
    use mpm_case_stability, only: start_time_step
    use mpm_case_output_fields, only: output_fields, nfields
    use mpm_case_guard, only: snapshot_in_memory
    use mpm_case_loads, only: load_line
    use mpm_case_motion, only: motion_line
    use mpm_case_strength_reduction, only: strength_reduction_line
    use mpm_case_pore_water, only: pore_water_summary
    implicit none

contains

    module procedure case_summary
        character(len=*), parameter :: nl = new_line("a")
        character(len=:), allocatable :: line
        integer :: d, m, b, f, dim
        integer(i8) :: count, total
        logical :: viscous
        real(wp) :: extent(3), critical

        dim = case%dim
        text = ""
        text = text//"case        "//text_or(case%name, "?")//" ("//text_or(case%file, "?")//")"//nl
        if (dim == 2) then
            text = text//"dimension   2 (plane strain)"//nl
        else
            text = text//"dimension   3"//nl
        end if
        line = "grid        "//int_list(case%domain%ncells(1:dim), " x ")//" cells, " &
            //int_list(case%domain%ncells(1:dim) + 1, " x ")//" = "//int_text(node_count(case)) &
            //" nodes, dx = "//fmt_real(case%domain%dx)//" m"
        text = text//line//nl
        extent(1:dim) = case%domain%origin(1:dim) + case%domain%ncells(1:dim)*case%domain%dx
        text = text//"domain      "//fmt_box(case%domain%origin(1:dim), extent(1:dim), domain_digits) &
            //" m (origin "//fmt_vector(case%domain%origin(1:dim))//")"//nl
        line = "boundaries "
        do d = 1, dim
            line = line//" "//face_text(case, 1, d)//", "//face_text(case, 2, d)
            if (d < dim) line = line//","
        end do
        text = text//line//nl
        line = "particles   ppc = "//int_text(case%particles%ppc)//" (" &
            //int_text(case%particles%ppc**dim)//" per cell), " &
            //trim(distribution_names(case%particles%distribution))
        if (case%particles%distribution == dist_random) line = line//", seed "//int_text(case%particles%seed)
        text = text//line//nl
        if (allocated(case%materials)) then
            text = text//"materials   "//int_text(size(case%materials))//nl
            do m = 1, size(case%materials)
                text = text//material_text(case%materials(m))
            end do
        end if
        if (allocated(case%bodies)) then
            if (size(case%bodies) == 0) then
                text = text//"bodies      none (the particles come from load_state)"//nl
            else
                total = 0
                do b = 1, size(case%bodies)
                    total = total + body_particles(case, b)
                end do
                text = text//"bodies      "//int_text(size(case%bodies))//", "//int_text(total) &
                    //" particles"//nl
            end if
            do b = 1, size(case%bodies)
                associate (body => case%bodies(b))
                    count = body_particles(case, b)
                    line = '  "'//text_or(body%name, "?")//'"'
                    if (allocated(case%materials)) then
                        if (body%material >= 1 .and. body%material <= size(case%materials)) then
                            line = line//' material "'//case%materials(body%material)%name//'"'
                        end if
                    end if
                    line = line//": "
                    if (allocated(body%polygon)) then
                        line = line//"polygon of "//int_text(size(body%polygon, 2)) &
                            //" vertices in "
                    else if (body%shape == shape_cylinder) then
                        line = line//"cylinder from "//fmt_vector(body%centre(1:dim))//" to " &
                            //fmt_vector(body%axis_end(1:dim))//", radius " &
                            //fmt_real(body%radius)//" m, in "
                    else if (body%shape /= shape_none) then
                        line = line//trim(merge("circle", "sphere", body%shape == shape_circle)) &
                            //" of centre "//fmt_vector(body%centre(1:dim))//", radius " &
                            //fmt_real(body%radius)//" m, in "
                    else if (allocated(body%list)) then
                        line = line//"particle list '"//body%list%file//"'"
                        if (allocated(body%list%stress)) line = line//" with stresses"
                        line = line//" in "
                    else if (allocated(body%bottom_file)) then
                        line = line//"layer below '"//body%file//"' above '"//body%bottom_file &
                            //"' in "
                    else if (allocated(body%file)) then
                        if (len(body%file) > 0) line = line//"surface '"//body%file//"' in "
                    end if
                    text = text//line//fmt_box(body%xmin(1:dim), body%xmax(1:dim)) &
                        //" m, v = "//fmt_vector(body%velocity(1:dim))//" m/s, " &
                        //int_text(count)//" particles"//nl
                end associate
            end do
        end if
        text = text//"gravity     "//fmt_vector(case%gravity(1:dim))//" m/s2"//nl
        text = text//"solver      scheme "//trim(scheme_names(case%solver%scheme))//", shape function " &
            //trim(case%solver%shape_function)
        if (case%solver%fbar) text = text//", F-bar locking correction"
        if (case%solver%apic) text = text//", APIC transfer"
        if (case%solver%xpic) text = text//", XPIC("//int_text(case%solver%xpic_order)//") transfer"
        if (case%solver%flip_fraction < 1.0_wp) text = text//", velocity update " &
            //fmt_real(case%solver%flip_fraction)//" FLIP + " &
            //fmt_real(1.0_wp - case%solver%flip_fraction)//" PIC"
        text = text//nl
        line = "time        tend = "//fmt_real(case%time%tend)//" s, "
        if (case%time%dt > 0.0_wp) then
            line = line//"dt = "//fmt_real(case%time%dt)//" s (fixed)"
        else
            line = line//"dt from CFL = "//fmt_real(case%time%cfl)
        end if
        if (allocated(case%materials)) then
            if (size(case%materials) > 0) then
                call start_time_step(case%dim, case%domain%dx, case%materials, case%bodies, critical, viscous)
                line = line//", critical time step "//fmt_real(critical, 6)//" s at t = 0"
                if (viscous .and. case%pore_water%on) then
                    line = line//" (viscous or pore-pressure diffusion limit)"
                else if (viscous) then
                    line = line//" (viscous limit)"
                end if
                if (stiffens(case%materials)) line = line//" at the least stiffness (it " &
                    //"follows the stress in the run)"
            end if
        end if
        if (case%time%allow_unstable) line = line//", allow_unstable (no stability check)"
        text = text//line//nl
        line = "damping     "//trim(damping_names(case%damping%type))
        if (case%damping%type == damping_local) line = line//", alpha = "//fmt_real(case%damping%value)
        text = text//line//nl
        if (case%pore_water%on) text = text//pore_water_summary(case%pore_water, &
            case%materials)//nl
        if (case%initial_stress%type == initial_k0) then
            line = "initial     geostatic stress,"
            do m = 1, size(case%materials)
                line = line//" "//case%materials(m)%name//" K0 = " &
                    //fmt_real(case%initial_stress%k0_material(m), 4)
                if (m < size(case%materials)) line = line//","
            end do
            text = text//line//nl
        end if
        if (allocated(case%loads)) then
            do m = 1, size(case%loads)
                text = text//"load        "//load_line(case%loads(m), case%dim, case%materials)//nl
            end do
        end if
        if (allocated(case%motions)) then
            do m = 1, size(case%motions)
                text = text//"motion      "//motion_line(case%motions(m), case%dim)//nl
            end do
        end if
        if (case%strength_reduction%enabled) text = text//"srm         " &
            //strength_reduction_line(case%strength_reduction)//nl
        text = text//"contact     "//text_or(case%contact%type, "none")//nl
        line = "output      "//text_or(case%output%directory, "?")
        if (case%output%interval > 0.0_wp) then
            line = line//", every "//fmt_real(case%output%interval)//" s"
            if (case_step(case) > case%output%interval) line = line//" (below the time step "// &
                fmt_real(case_step(case), 6)//" s at t = 0: an output every step)"
        else
            line = line//", initial and final state only"
        end if
        line = line//", grid "//yes_no(case%output%grid)//", overwrite "//yes_no(case%output%overwrite)
        text = text//line//nl
        line = "fields     "
        do f = 1, nfields
            if (case%output%fields(f)) line = line//" "//trim(output_fields(f)%name)
        end do
        text = text//line//nl
        if (case%output%history_interval > 0.0_wp) then
            text = text//"history     every "//fmt_real(case%output%history_interval)//" s"//nl
        else
            text = text//"history     every time step"//nl
        end if
        text = text//"progress    every "//fmt_real(case%progress%interval)//" s (wall clock)"//nl
        text = text//"save_state  "//text_or(case%save_state, "(none)", empty_too=.true.)//nl
        text = text//"load_state  "//text_or(case%load_state, "(none)", empty_too=.true.)//nl
        line = "checkpoint "
        if (case%checkpoint%every_steps > 0) line = line//" every "//int_text(case%checkpoint%every_steps)// &
            " steps,"
        if (case%checkpoint%every_minutes > 0.0_wp) line = line//" every "// &
            fmt_real(case%checkpoint%every_minutes)//" min,"
        if (case%checkpoint%on_signal) then
            line = line//" on SIGTERM/SIGINT"
        else
            line = line//" not on signals"
        end if
        line = line//", file "//text_or(case%checkpoint%file, "<output folder>/checkpoint.h5", &
            empty_too=.true.)
        text = text//line//nl
        line = "guard       energy created above "//fmt_real(case%guard%energy_factor)// &
            " x the energy scale; "
        if (case%guard%snapshot_steps > 0) then
            line = line//"healthy copy every "//int_text(case%guard%snapshot_steps)//" steps"
            if (case%guard%snapshot_in == snapshot_in_memory) then
                line = line//", in memory"
            else
                line = line//", in <output folder>/.last_healthy.h5"
            end if
        else
            line = line//"no healthy copy"
        end if
        text = text//line
    end procedure case_summary

    !> materials).
    pure real(wp) function case_step(case)
        type(case_type), intent(in) :: case
            !! resolved case

        real(wp) :: critical
        logical :: viscous

        case_step = case%time%dt
        if (case_step > 0.0_wp) return
        case_step = 0.0_wp
        if (.not. allocated(case%materials)) return
        if (size(case%materials) == 0) return
        call start_time_step(case%dim, case%domain%dx, case%materials, case%bodies, critical, viscous)
        case_step = case%time%cfl*critical
    end function case_step

    !> Whether a material stiffens with its stress (its critical step follows it in the run).
    pure logical function stiffens(materials)
        type(material_spec_type), intent(in) :: materials(:)
            !! the materials

        integer :: m

        stiffens = .false.
        do m = 1, size(materials)
            if (allocated(materials(m)%law)) stiffens = stiffens .or. materials(m)%law%speed_varies()
        end do
    end function stiffens

    !> Number of grid nodes of the case.
    pure integer(i8) function node_count(case)
        type(case_type), intent(in) :: case
            !! resolved case

        node_count = product(int(case%domain%ncells(1:case%dim), i8) + 1_i8)
    end function node_count

    !> Particles of body b: the reader's count, or counted now for a case made in code.
    integer(i8) function body_particles(case, b)
        type(case_type), intent(in) :: case
            !! case
        integer, intent(in) :: b
            !! body index

        body_particles = case%bodies(b)%particles
        if (body_particles < 0) body_particles = body_site_count(case%dim, case%domain, &
            case%particles, case%bodies, b)
    end function body_particles

    !> The lines of a material: its name and type, then its law's lines.
    pure function material_text(mat) result(text)
        type(material_spec_type), intent(in) :: mat
            !! resolved material
        character(len=:), allocatable :: text

        character(len=:), allocatable :: lines

        text = '  "'//text_or(mat%name, "?")//'" '//text_or(mat%type, "?")//": "
        if (allocated(mat%law)) then
            call mat%law%summary(lines)
            text = text//lines
        else
            text = text//new_line("a")
        end if
    end function material_text

    !> "xmin fixed", "ymin frictional (mu = 0.4)"
    pure function face_text(case, side, axis) result(text)
        type(case_type), intent(in) :: case
            !! resolved case
        integer, intent(in) :: side
            !! 1: min face, 2: max face
        integer, intent(in) :: axis
            !! axis of the face
        character(len=:), allocatable :: text

        text = axis_names(axis:axis)//trim(merge("min", "max", side == 1))//" " &
            //case%domain%face_text(side, axis)
    end function face_text

end submodule mpm_case_summary
